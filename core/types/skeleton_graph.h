// A rooted 3D branching graph: the tree skeleton.
//
// Nodes hold indices, not pointers: node i's parent is nodes[i].parent_idx
// (-1 for the root). Invariants (Check()): exactly one root; parent indices
// are valid and acyclic; positions finite; radii >= 0.
#ifndef SYLVA_CORE_TYPES_SKELETON_GRAPH_H_
#define SYLVA_CORE_TYPES_SKELETON_GRAPH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace sylva {

struct SkeletonNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world units
  double radius = 0.0;                                 // world units
  int parent_idx = -1;                                 // -1 for the root
  int order = 0;  // branch order: 0 = trunk, 1 = its branches, ...
};

class SkeletonGraph {
 public:
  std::vector<SkeletonNode> nodes;
  // What the radii are: "ground truth" for synthetic trees, or an
  // "allometric prior" (estimated, not measured) for reconstructions.
  std::string radius_source = "unknown";

  int NumNodes() const { return static_cast<int>(nodes.size()); }
  int AddNode(const Eigen::Vector3d& position, double radius, int parent_idx, int order);
  int RootIdx() const;  // -1 if empty
  // Children lists, indexed like nodes.
  std::vector<std::vector<int>> Children() const;
  // Sum of edge lengths.
  double TotalLength() const;
  // Points sampled along every edge at most `spacing` apart (plus the nodes).
  std::vector<Eigen::Vector3d> SamplePoints(double spacing) const;

  // Throws Error naming the broken invariant.
  void Check() const;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_SKELETON_GRAPH_H_
