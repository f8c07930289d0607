// MinNonAdjacentCapsuleDistance (sketch/gesture_tree.h) over the capsules
// of sketch/gesture_geometry.h.
#include <limits>

#include "core/geometry/polyline.h"
#include "sketch/gesture_geometry.h"
#include "sketch/gesture_tree.h"

namespace sylva {

using gesture_internal::Capsule;
using gesture_internal::CapsuleGrid;
using gesture_internal::kAdjacentReach;
using gesture_internal::TreePaths;

double MinNonAdjacentCapsuleDistance(const SkeletonGraph& skeleton) {
  // Paths from the root, nodes in breadth-first order.
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> order = {skeleton.RootIdx()}, rank(skeleton.nodes.size(), -1);
  TreePaths paths;
  double longest = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    const int node = order[k];
    const int parent = skeleton.nodes[node].parent_idx;
    const double length =
        parent < 0 ? 0.0 : (skeleton.nodes[node].position - skeleton.nodes[parent].position).norm();
    longest = std::max(longest, length);
    rank[node] = static_cast<int>(k);
    paths.Add(parent < 0 ? -1 : rank[parent], length);
    for (int child : children[node]) order.push_back(child);
  }
  CapsuleGrid grid(std::max(longest, 1e-9));
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const int b = static_cast<int>(&node - skeleton.nodes.data());
    grid.Add({skeleton.nodes[node.parent_idx].position, node.position, node.radius,
              rank[node.parent_idx], rank[b], b});
  }
  double smallest = std::numeric_limits<double>::infinity();
  for (const Capsule& c : grid.capsules()) {
    Capsule reach = c;
    reach.radius += 2 * longest;  // candidates within a generous box
    grid.Near(reach, [&](int index) {
      const Capsule& o = grid.capsules()[index];
      if (o.module <= c.module) return;
      if (paths.BetweenEdges(c.node_a, c.node_b, o.node_a, o.node_b) <=
          kAdjacentReach * (c.radius + o.radius))
        return;
      Eigen::Vector3d cp, co;
      smallest =
          std::min(smallest, std::sqrt(SegmentSegmentDistance2(c.a, c.b, o.a, o.b, &cp, &co)) -
                                 c.radius - o.radius);
    });
  }
  return smallest;
}

}  // namespace sylva
