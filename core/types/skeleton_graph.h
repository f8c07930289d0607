// A rooted 3D branching graph: the tree skeleton.
//
// Nodes hold indices, not pointers: node i's parent is nodes[i].parent_idx
// (-1 for the root). Invariants (Check()): exactly one root; parent indices
// are valid and acyclic; positions finite; radii >= 0.
#ifndef SYLVA_CORE_TYPES_SKELETON_GRAPH_H_
#define SYLVA_CORE_TYPES_SKELETON_GRAPH_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace sylva {

struct SkeletonNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world units
  double radius = 0.0;                                 // world units
  int parent_idx = -1;                                 // -1 for the root
  int order = 0;  // branch order: 0 = trunk, 1 = its branches, ...
  // Particles ("strands" of the pipe model, thesis 5.1) carried by the edge
  // from this node to its parent; for the root, all of them. 0 = unknown.
  int strands = 0;
};

// One branch axis: a chain of node indices from where the branch leaves its
// parent axis (that junction node is the chain's first element; the root for
// the trunk) to a tip.
using BranchAxis = std::vector<int>;

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
  // Tips (nodes without children).
  std::vector<int> Tips() const;

  // Splits the tree into branch axes: the trunk from the root, following at
  // every node the child carrying the most strands (then the thickest, then
  // the lowest index); every other child starts a new axis of the next order.
  // Axes are listed trunk first, then by order, then in order of discovery.
  // `orders` (optional) receives each axis' branch order.
  std::vector<BranchAxis> BranchAxes(std::vector<int>* orders = nullptr) const;
  // The same split with another rule for the child an axis continues into:
  // `continuation(node, children)` returns one of `children`, or -1 to end
  // the axis at `node` (every child then starts a new axis).
  using ContinuationRule = std::function<int(int node, const std::vector<int>& children)>;
  std::vector<BranchAxis> BranchAxes(const ContinuationRule& continuation,
                                     std::vector<int>* orders) const;
  // The axis (index into `axes`, from BranchAxes()) each node lies on: a
  // junction node lies on the axis it continues, the root on the trunk.
  std::vector<int> AxisOfNodes(const std::vector<BranchAxis>& axes) const;
  // Sets every node's `order` from BranchAxes() (a junction node keeps the
  // order of the axis it continues).
  void AssignOrders();
  // Sum of edge lengths.
  double TotalLength() const;
  // The tree's height: how far the highest node lies above the root node
  // along +Z (the up axis), in world units; 0 for an empty skeleton. Every
  // stage that scales by the tree's size uses this one definition.
  double Height() const;
  // Points sampled along every edge at most `spacing` apart (plus the nodes).
  std::vector<Eigen::Vector3d> SamplePoints(double spacing) const;

  // Throws Error naming the broken invariant.
  void Check() const;
};

// Distances along a skeleton's edges, taken when constructed (later edits of
// the skeleton are not seen). Parents need not come before their children.
class SkeletonPathLengths {
 public:
  explicit SkeletonPathLengths(const SkeletonGraph& skeleton);

  // How far `point`, on the edge from `node`'s parent to `node`, lies from
  // the root along the skeleton.
  double FromRoot(int node, const Eigen::Vector3d& point) const;
  // The distance along the skeleton between a point on the edge ending at
  // `a` (`from_root_a` from the root) and one on the edge ending at `b`.
  double Between(int a, double from_root_a, int b, double from_root_b) const;

 private:
  std::vector<int> parents_, levels_;  // levels_: edges from the root
  std::vector<double> depths_;         // each node's distance from the root
  std::vector<Eigen::Vector3d> positions_;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_SKELETON_GRAPH_H_
