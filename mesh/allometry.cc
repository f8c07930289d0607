#include "mesh/allometry.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Nodes in breadth-first order from the root: every parent before its children.
std::vector<int> ParentsFirstOrder(const SkeletonGraph& skeleton) {
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> order = {skeleton.RootIdx()};
  for (size_t k = 0; k < order.size(); ++k) {
    for (int child : children[order[k]]) order.push_back(child);
  }
  return order;
}

}  // namespace

std::vector<double> EffectivePipeStrands(const SkeletonGraph& skeleton) {
  std::vector<double> effective(skeleton.nodes.size(), 0.0);
  if (skeleton.nodes.empty()) return effective;
  const std::vector<int> order = ParentsFirstOrder(skeleton);
  std::vector<double> children_sum(skeleton.nodes.size(), 0.0);
  // Children before parents: each node's children are complete when it is reached.
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const SkeletonNode& node = skeleton.nodes[*it];
    const double from_children = children_sum[*it] > 0 ? children_sum[*it] : 1.0;
    effective[*it] = std::max(static_cast<double>(node.strands), from_children);
    if (node.parent_idx >= 0) children_sum[node.parent_idx] += effective[*it];
  }
  return effective;
}

void AssignPipeModelRadii(const AllometryOptions& options, SkeletonGraph* skeleton) {
  options.Check();
  SYLVA_CHECK(skeleton != nullptr);
  skeleton->Check();
  if (skeleton->nodes.empty()) return;
  const std::vector<double> strands = EffectivePipeStrands(*skeleton);
  const double root_strands = strands[skeleton->RootIdx()];
  const double inverse_exponent = 1.0 / options.diameter_exponent;
  for (int i = 0; i < skeleton->NumNodes(); ++i) {
    const double radius =
        options.trunk_radius * std::pow(strands[i] / root_strands, inverse_exponent);
    skeleton->nodes[i].radius = std::max(options.min_radius, radius);
  }
  skeleton->radius_source = kAllometricPrior;
}

}  // namespace sylva
