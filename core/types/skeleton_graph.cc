#include "core/types/skeleton_graph.h"

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

double SkeletonGraph::TotalLength() const {
  double length = 0.0;
  for (const SkeletonNode& node : nodes) {
    if (node.parent_idx >= 0) length += (node.position - nodes[node.parent_idx].position).norm();
  }
  return length;
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
