#include "core/types/skeleton_graph.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {

int SkeletonGraph::AddNode(const Eigen::Vector3d& position, double radius, int parent_idx,
                           int order) {
  SYLVA_CHECK(parent_idx >= -1 && parent_idx < NumNodes());
  nodes.push_back({position, radius, parent_idx, order});
  return NumNodes() - 1;
}

int SkeletonGraph::RootIdx() const {
  for (int i = 0; i < NumNodes(); ++i) {
    if (nodes[i].parent_idx < 0) return i;
  }
  return -1;
}

std::vector<std::vector<int>> SkeletonGraph::Children() const {
  std::vector<std::vector<int>> children(nodes.size());
  for (int i = 0; i < NumNodes(); ++i) {
    if (nodes[i].parent_idx >= 0) children[nodes[i].parent_idx].push_back(i);
  }
  return children;
}

std::vector<int> SkeletonGraph::Tips() const {
  std::vector<int> tips;
  const std::vector<std::vector<int>> children = Children();
  for (int i = 0; i < NumNodes(); ++i) {
    if (children[i].empty()) tips.push_back(i);
  }
  return tips;
}

namespace {

// The child an axis continues into: most strands, then thickest, then lowest index.
int ContinuationChild(const SkeletonGraph& graph, const std::vector<int>& children) {
  int best = -1;
  for (int child : children) {
    if (best < 0) {
      best = child;
      continue;
    }
    const SkeletonNode& c = graph.nodes[child];
    const SkeletonNode& b = graph.nodes[best];
    if (c.strands > b.strands || (c.strands == b.strands && c.radius > b.radius)) best = child;
  }
  return best;
}

}  // namespace

std::vector<int> SkeletonGraph::AxisOfNodes(const std::vector<BranchAxis>& axes) const {
  std::vector<int> axis_of(nodes.size(), 0);
  for (size_t a = 1; a < axes.size(); ++a) {
    for (size_t k = 1; k < axes[a].size(); ++k) axis_of[axes[a][k]] = static_cast<int>(a);
  }
  return axis_of;
}

std::vector<BranchAxis> SkeletonGraph::BranchAxes(std::vector<int>* orders) const {
  return BranchAxes(
      [this](int, const std::vector<int>& children) { return ContinuationChild(*this, children); },
      orders);
}

std::vector<BranchAxis> SkeletonGraph::BranchAxes(const ContinuationRule& continuation,
                                                  std::vector<int>* orders) const {
  std::vector<BranchAxis> axes;
  std::vector<int> axis_orders;
  const int root = RootIdx();
  if (root < 0) return axes;
  const std::vector<std::vector<int>> children = Children();
  // Breadth-first over axes: (junction node, first node of the axis, order).
  struct Start {
    int junction, first, order;
  };
  std::vector<Start> queue = {{-1, root, 0}};
  for (size_t q = 0; q < queue.size(); ++q) {
    const Start start = queue[q];
    BranchAxis axis;
    if (start.junction >= 0) axis.push_back(start.junction);
    for (int node = start.first; node >= 0;) {
      axis.push_back(node);
      const int next = continuation(node, children[node]);
      for (int child : children[node]) {
        if (child != next) queue.push_back({node, child, start.order + 1});
      }
      node = next;
    }
    axes.push_back(std::move(axis));
    axis_orders.push_back(start.order);
  }
  if (orders != nullptr) *orders = std::move(axis_orders);
  return axes;
}

void SkeletonGraph::AssignOrders() {
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = BranchAxes(&orders);
  for (size_t a = 0; a < axes.size(); ++a) {
    // Skip the junction node, which belongs to the parent axis.
    for (size_t k = (a == 0 ? 0 : 1); k < axes[a].size(); ++k) nodes[axes[a][k]].order = orders[a];
  }
}

double SkeletonGraph::TotalLength() const {
  double length = 0.0;
  for (const SkeletonNode& node : nodes) {
    if (node.parent_idx >= 0) length += (node.position - nodes[node.parent_idx].position).norm();
  }
  return length;
}

SkeletonPathLengths::SkeletonPathLengths(const SkeletonGraph& skeleton) {
  const int n = skeleton.NumNodes();
  parents_.resize(n);
  positions_.resize(n);
  for (int i = 0; i < n; ++i) {
    parents_[i] = skeleton.nodes[i].parent_idx;
    positions_[i] = skeleton.nodes[i].position;
  }
  levels_.assign(n, -1);
  depths_.assign(n, 0.0);
  std::vector<int> path;
  for (int start = 0; start < n; ++start) {
    path.clear();
    for (int k = start; k >= 0 && levels_[k] < 0; k = parents_[k]) path.push_back(k);
    for (auto it = path.rbegin(); it != path.rend(); ++it) {
      const int parent = parents_[*it];
      if (parent < 0) {
        levels_[*it] = 0;
        continue;
      }
      levels_[*it] = levels_[parent] + 1;
      depths_[*it] = depths_[parent] + (positions_[*it] - positions_[parent]).norm();
    }
  }
}

double SkeletonPathLengths::FromRoot(int node, const Eigen::Vector3d& point) const {
  const int parent = parents_[node];
  return parent < 0 ? 0.0 : depths_[parent] + (point - positions_[parent]).norm();
}

double SkeletonPathLengths::Between(int a, double from_root_a, int b, double from_root_b) const {
  int u = a, v = b;
  while (levels_[u] > levels_[v]) u = parents_[u];
  while (levels_[v] > levels_[u]) v = parents_[v];
  while (u != v) u = parents_[u], v = parents_[v];
  // One point on the other's way to the root (they meet at one of their
  // edges' end nodes): the difference of their distances from the root.
  if (u == a || u == b) return std::abs(from_root_a - from_root_b);
  return (from_root_a - depths_[u]) + (from_root_b - depths_[u]);
}

double SkeletonGraph::Height() const {
  const int root = RootIdx();
  if (root < 0) return 0.0;
  double top = nodes[root].position.z();
  for (const SkeletonNode& node : nodes) top = std::max(top, node.position.z());
  return top - nodes[root].position.z();
}

std::vector<Eigen::Vector3d> SkeletonGraph::SamplePoints(double spacing) const {
  SYLVA_CHECK(spacing > 0);
  std::vector<Eigen::Vector3d> points;
  for (const SkeletonNode& node : nodes) {
    points.push_back(node.position);
    if (node.parent_idx < 0) continue;
    const Eigen::Vector3d& parent = nodes[node.parent_idx].position;
    const int steps = static_cast<int>(std::ceil((node.position - parent).norm() / spacing));
    for (int s = 1; s < steps; ++s) {
      points.push_back(parent + (node.position - parent) * (static_cast<double>(s) / steps));
    }
  }
  return points;
}

void SkeletonGraph::Check() const {
  int roots = 0;
  for (int i = 0; i < NumNodes(); ++i) {
    const SkeletonNode& node = nodes[i];
    SYLVA_CHECK(node.parent_idx >= -1 && node.parent_idx < NumNodes())
        << "node " << i << " has parent " << node.parent_idx;
    SYLVA_CHECK(node.position.allFinite()) << "node " << i << " position is not finite";
    SYLVA_CHECK(node.radius >= 0 && std::isfinite(node.radius)) << "node " << i << " radius";
    SYLVA_CHECK(node.strands >= 0) << "node " << i << " has " << node.strands << " strands";
    if (node.parent_idx < 0) ++roots;
  }
  SYLVA_CHECK(nodes.empty() || roots == 1) << "skeleton has " << roots << " roots";
  // Acyclic: walking up from any node reaches the root in < N steps.
  for (int i = 0; i < NumNodes(); ++i) {
    int steps = 0;
    for (int j = i; j >= 0; j = nodes[j].parent_idx) {
      SYLVA_CHECK(++steps <= NumNodes()) << "skeleton has a cycle through node " << i;
    }
  }
}

}  // namespace sylva
