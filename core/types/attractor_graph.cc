#include "core/types/attractor_graph.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// The graph's kept nodes, in their order, each linked to its nearest kept
// ancestor.
AttractorGraph2D KeepNodes(const AttractorGraph2D& graph, const std::vector<char>& kept) {
  const int n = graph.NumNodes();
  AttractorGraph2D out;
  out.width = graph.width;
  out.height = graph.height;
  out.source = graph.source;
  std::vector<int> index_of(n, -1);
  for (int i = 0; i < n; ++i) {
    if (kept[i])
      index_of[i] = static_cast<int>(out.nodes.size()), out.nodes.push_back(graph.nodes[i]);
  }
  for (int i = 0; i < n; ++i) {
    if (!kept[i]) continue;
    int parent = graph.nodes[i].parent_idx;
    while (parent >= 0 && !kept[parent]) parent = graph.nodes[parent].parent_idx;
    out.nodes[index_of[i]].parent_idx = parent < 0 ? -1 : index_of[parent];
  }
  out.root = graph.root < 0 ? -1 : index_of[graph.root];
  return out;
}

}  // namespace

int AttractorGraph2D::AddNode(const Eigen::Vector2d& position, int parent_idx) {
  SYLVA_CHECK(parent_idx >= -1 && parent_idx < NumNodes());
  nodes.push_back({position, parent_idx});
  return NumNodes() - 1;
}

int AttractorGraph2D::NumEdges() const {
  int edges = 0;
  for (const AttractorNode& node : nodes) edges += node.parent_idx >= 0;
  return edges;
}

std::vector<int> AttractorGraph2D::Roots() const {
  std::vector<int> roots;
  for (int i = 0; i < NumNodes(); ++i) {
    if (nodes[i].parent_idx < 0) roots.push_back(i);
  }
  return roots;
}

std::vector<std::vector<int>> AttractorGraph2D::Children() const {
  std::vector<std::vector<int>> children(nodes.size());
  for (int i = 0; i < NumNodes(); ++i) {
    if (nodes[i].parent_idx >= 0) children[nodes[i].parent_idx].push_back(i);
  }
  return children;
}

double AttractorGraph2D::TotalLength() const {
  double length = 0;
  for (const auto& [a, b] : Segments()) length += (b - a).norm();
  return length;
}

std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> AttractorGraph2D::Segments() const {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments;
  segments.reserve(nodes.size());
  for (const AttractorNode& node : nodes) {
    if (node.parent_idx >= 0) segments.emplace_back(node.position, nodes[node.parent_idx].position);
  }
  return segments;
}

std::vector<Eigen::Vector2d> AttractorGraph2D::SamplePoints(double spacing) const {
  SYLVA_CHECK(spacing > 0);
  std::vector<Eigen::Vector2d> points;
  for (const AttractorNode& node : nodes) points.push_back(node.position);
  for (const auto& [a, b] : Segments()) {
    const int steps = static_cast<int>(std::ceil((b - a).norm() / spacing));
    for (int k = 1; k < steps; ++k)
      points.push_back(a + (b - a) * (static_cast<double>(k) / steps));
  }
  return points;
}

AttractorGraph2D AttractorGraph2D::Simplified(double tolerance) const {
  const int n = NumNodes();
  std::vector<int> num_children(n, 0);
  for (const AttractorNode& node : nodes) {
    if (node.parent_idx >= 0) ++num_children[node.parent_idx];
  }
  std::vector<char> kept(n);
  for (int i = 0; i < n; ++i)
    kept[i] = nodes[i].parent_idx < 0 || num_children[i] != 1 || i == root;
  if (tolerance > 0) {
    std::vector<int> chain;
    std::vector<char> keep;
    for (int start = 0; start < n; ++start) {
      if (!kept[start] || nodes[start].parent_idx < 0) continue;
      chain.assign(1, start);
      int node = nodes[start].parent_idx;
      while (!kept[node]) {
        chain.push_back(node);
        node = nodes[node].parent_idx;
      }
      chain.push_back(node);
      keep.assign(chain.size(), 0);
      DouglasPeucker(
          static_cast<int>(chain.size()), [&](int k) { return nodes[chain[k]].position; },
          tolerance, &keep);
      for (size_t k = 0; k < chain.size(); ++k) {
        if (keep[k]) kept[chain[k]] = 1;
      }
    }
  } else {
    kept.assign(n, 1);
  }
  return KeepNodes(*this, kept);
}

AttractorGraph2D AttractorGraph2D::WithoutTwigs(double min_length) const {
  const int n = NumNodes();
  std::vector<char> removed(n, 0);
  std::vector<int> num_children(n, 0);
  for (const AttractorNode& node : nodes) {
    if (node.parent_idx >= 0) ++num_children[node.parent_idx];
  }
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<int> chain;
    for (int tip = 0; tip < n; ++tip) {
      if (removed[tip] || num_children[tip] != 0 || nodes[tip].parent_idx < 0) continue;
      // Down to the first node with other children, or a root.
      chain.assign(1, tip);
      double length = 0;
      int node = tip;
      while (nodes[node].parent_idx >= 0) {
        const int parent = nodes[node].parent_idx;
        length += (nodes[parent].position - nodes[node].position).norm();
        if (num_children[parent] > 1 || nodes[parent].parent_idx < 0) {
          node = parent;
          break;
        }
        chain.push_back(parent);
        node = parent;
      }
      // `node` is the junction or root the twig hangs from.
      if (length >= min_length || num_children[node] < 2) continue;
      for (int c : chain) removed[c] = 1;
      --num_children[node];
      changed = true;
    }
  }
  std::vector<char> kept(n);
  for (int i = 0; i < n; ++i) kept[i] = !removed[i];
  return KeepNodes(*this, kept);
}

AttractorGraph2D AttractorGraph2D::Scaled(double scale) const {
  AttractorGraph2D out = *this;
  out.width = std::max(1, static_cast<int>(std::lround(width * scale)));
  out.height = std::max(1, static_cast<int>(std::lround(height * scale)));
  for (AttractorNode& node : out.nodes) node.position *= scale;
  return out;
}

bool AttractorGraph2D::FitsAspectOf(int image_width, int image_height) const {
  if (width <= 0 || height <= 0) return false;
  const double scale_x = static_cast<double>(image_width) / width;
  const double scale_y = static_cast<double>(image_height) / height;
  return std::abs(scale_x - scale_y) < kGraphAspectTolerance * scale_x;
}

void AttractorGraph2D::Check(const std::string& source_name) const {
  SYLVA_CHECK_INPUT(width > 0 && height > 0, source_name)
      << "the attractor graph's image size must be positive, got " << width << " x " << height;
  const int n = NumNodes();
  for (int i = 0; i < n; ++i) {
    SYLVA_CHECK_INPUT(nodes[i].position.allFinite(), source_name)
        << "node " << i << " has a non-finite position";
    const int parent = nodes[i].parent_idx;
    SYLVA_CHECK_INPUT(parent >= -1 && parent < n && parent != i, source_name)
        << "node " << i << " has an invalid parent " << parent << " (" << n << " nodes)";
  }
  // Acyclic: following parents from any node reaches a root within n steps.
  std::vector<char> state(n, 0);  // 0 unseen, 1 on the current path, 2 reaches a root
  std::vector<int> path;
  for (int i = 0; i < n; ++i) {
    path.clear();
    int node = i;
    while (node >= 0 && state[node] == 0) {
      state[node] = 1;
      path.push_back(node);
      node = nodes[node].parent_idx;
    }
    SYLVA_CHECK_INPUT(node < 0 || state[node] == 2, source_name)
        << "the edges of the attractor graph form a cycle through node " << node;
    for (int p : path) state[p] = 2;
  }
  if (n == 0) {
    SYLVA_CHECK_INPUT(root == -1, source_name) << "an empty attractor graph has no root";
  } else {
    SYLVA_CHECK_INPUT(root >= 0 && root < n && nodes[root].parent_idx < 0, source_name)
        << "the root (" << root << ") must be a node without a parent";
  }
}

}  // namespace sylva
