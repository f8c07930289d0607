// A 2D attractor graph (thesis 3.2.2): the trunk and main branches of a tree
// as seen in one photo, traced by livewire or drawn by a person, in that
// photo's pixel coordinates (COLMAP's convention: the centre of pixel (i, j)
// at (i + 0.5, j + 0.5)). The direction fields of simulate/ turn it into the
// steering of the particle flow (thesis 3.5).
//
// The graph is a forest whose edges point down the tree: node i's parent
// (parent_idx) is the next node towards the tree base; a node without a
// parent is a root. The main root (the tree base or the first branching on
// the trunk, where livewire paths end) is `root`; drawn strokes that touch
// nothing else form further components with roots of their own. The
// direction "down the graph" at a point of edge (i -> parent) is
// unit(parent - i).
#ifndef SYLVA_CORE_TYPES_ATTRACTOR_GRAPH_H_
#define SYLVA_CORE_TYPES_ATTRACTOR_GRAPH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace sylva {

// How far the aspect ratio of the image a graph was made for may differ from
// its photo's (AttractorGraph2D::FitsAspectOf), as a fraction of the scale
// between them (dimensionless). A graph drawn on a resized copy of the photo
// is scaled to the photo; rounding the copy's size to whole pixels changes
// its aspect by up to one pixel in its shorter side, so 1 % accepts copies
// down to about 100 pixels a side and still refuses a crop or a rotated
// photo.
constexpr double kGraphAspectTolerance = 0.01;

struct AttractorNode {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // pixels
  int parent_idx = -1;                                 // towards the base; -1 = a root
};

class AttractorGraph2D {
 public:
  // The size of the image the coordinates refer to, in pixels (> 0).
  int width = 0;
  int height = 0;
  std::vector<AttractorNode> nodes;
  // The main root (-1 when there are no nodes).
  int root = -1;
  // Where the graph comes from: "livewire", "strokes", "edited", ...
  std::string source;

  int NumNodes() const { return static_cast<int>(nodes.size()); }
  bool IsEmpty() const { return nodes.empty(); }
  // Appends a node; parent_idx must be -1 or an existing node.
  int AddNode(const Eigen::Vector2d& position, int parent_idx);
  // Edges (node -> parent), i.e. nodes with a parent.
  int NumEdges() const;
  // Nodes without a parent, ascending.
  std::vector<int> Roots() const;
  std::vector<std::vector<int>> Children() const;
  // Sum of edge lengths, in pixels.
  double TotalLength() const;
  // Points along every edge at most `spacing` pixels apart, plus the nodes.
  std::vector<Eigen::Vector2d> SamplePoints(double spacing) const;
  // Segments (node position, parent position), one per edge, in node order.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> Segments() const;

  // The same graph with nodes on chains of degree-2 nodes dropped while
  // every dropped node stays within `tolerance` pixels of the kept polyline
  // (Douglas-Peucker per chain); roots, tips and junctions are kept. Node
  // order: kept nodes in their original order.
  AttractorGraph2D Simplified(double tolerance) const;
  // The graph without its short twigs: repeatedly, every chain from a tip
  // down to the nearest junction (a node with two or more children) or root
  // that is shorter than `min_length` pixels is removed, until none is; the
  // chain ending at a root without other children (a lone stroke) stays.
  // Kept nodes keep their order.
  AttractorGraph2D WithoutTwigs(double min_length) const;
  // The graph in an image scaled by `scale` (positions times scale, size
  // rounded).
  AttractorGraph2D Scaled(double scale) const;
  // Whether the graph's image (positive size) has the aspect of an
  // image_width x image_height image: the scales from one to the other
  // along x and y differ by less than kGraphAspectTolerance of the x scale.
  bool FitsAspectOf(int image_width, int image_height) const;

  // Throws InputError naming `source_name` if the size is not positive, a
  // position is not finite, a parent index is invalid, the parents form a
  // cycle, or `root` is not a root (or not -1 for an empty graph).
  void Check(const std::string& source_name) const;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_ATTRACTOR_GRAPH_H_
