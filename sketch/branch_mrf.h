// Drawn branch strokes -> 3D branches by a Markov random field (Chen et al.
// 2008, "Sketch-based tree modeling using Markov random field", sections
// 4-7; thesis chapter 4).
//
// A drawing fixes where every branch segment's end lies across the line of
// sight; its depth along the line of sight is unknown. The drawn tree is a
// Markov tree: one node per segment, whose variable is the depth of its end,
// and whose factors tie each segment to its parent through the tree's global
// parameters Omega (the length ratio and the angle between a parent and its
// apical or lateral child, as normal distributions), plus a branch
// interaction term that pushes segments towards free space (eq. of section
// 5.2.1: P_d = prod_v exp(-k_e d_v / (1 + |p - p_v|^2)) over a 25^3 voxel
// grid of branch density d_v). Inference:
//   1. Omega's prior comes from the exemplar (template) whose projected
//      footprint is nearest the drawing's (section 7: the crown's aspect and
//      the 2D length ratio and apical / lateral angles of the drawn
//      segments, compared over 8 azimuths of each exemplar);
//   2. bottom-up ancestral inference: from the root, each segment takes the
//      depth that maximises its factor given its parent and the branches
//      already placed;
//   3. interpenetrating segments are pushed apart along the line of sight;
//   4. ICM: every depth in turn moves to the best value given its
//      neighbours (its own, its children's and grandchildren's factors and
//      the interaction term) until the depths change by less than epsilon;
//   5. EM over Omega (section 5.3): Omega is re-estimated from the 3D
//      segments (a MAP blend with the template's, MrfOptions::prior_weight
//      exemplar segments' worth) and ICM runs again, until Omega settles.
// Then self-similar propagation (section 6): replication blocks (a segment
// with its child segments, taken from the inferred tree, or the template's
// when the drawing has no fork) are scaled and turned onto open (tip)
// segments generation after generation, clipped to the crown (a surface of
// local revolution of the drawn crown outline) or stopped after a fixed
// number of generations without one.
//
// Units: any, as long as the drawing's positions and the exemplars'
// skeletons are in the same ones (the sketch mode uses metres).
#ifndef SYLVA_SKETCH_BRANCH_MRF_H_
#define SYLVA_SKETCH_BRANCH_MRF_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

// A tree of straight segments: segment i runs from points[parent[i]] to
// points[i]; the root (parent -1) is a point only. Parents come before
// their children.
struct SegmentTree {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> parent;

  int Size() const { return static_cast<int>(points.size()); }
  int AddPoint(const Eigen::Vector3d& point, int parent_idx);
  std::vector<std::vector<int>> Children() const;
  // The child of `node` that continues it (the smallest angle to node's own
  // segment, measured after dropping coordinate `drop_axis` if it is 0-2:
  // the 2D rule of section 7 for drawings); -1 if none.
  std::vector<int> ApicalChildren(int drop_axis = -1) const;
};

// One skeleton as a segment tree: the root, the junctions and the tips
// kept, chains between them simplified (Douglas-Peucker) to within
// `tolerance` (infinity: one segment from fork to fork).
SegmentTree SegmentTreeOfSkeleton(const SkeletonGraph& skeleton, double tolerance);

// A normal distribution of one parent-child relation.
struct RelationStatistics {
  double scale_mean = 0.8;  // |child| / |parent|
  double scale_sd = 0.3;
  double angle_mean = 0.5;  // radians between parent and child directions
  double angle_sd = 0.25;
  int count = 0;  // relations it was learnt from
};

// Omega: the global tree parameters.
struct TreeParameters {
  RelationStatistics apical, lateral;
};

// Omega learnt from a 3D segment tree (every segment with a parent
// segment; the apical child of each segment by the 3D rule). Relations of
// a kind that does not occur keep the defaults with count 0.
TreeParameters LearnTreeParameters(const SegmentTree& tree);

// The footprint of a tree in one view (section 7), from 2D positions (x
// across, y up; scale-free).
struct Footprint {
  double aspect = 1.0;      // width / height of the points' bounding box
  double scale_2d = 0.8;    // mean 2D length ratio child / parent
  double apical_2d = 0.3;   // mean 2D angle of apical children (radians)
  double lateral_2d = 0.8;  // mean 2D angle of lateral children
  double Distance(const Footprint& other) const;
};
Footprint FootprintOf(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& parent);

struct TreeExemplar {
  std::string name;
  SegmentTree tree;  // up = +Z
  TreeParameters parameters;
  std::vector<Footprint> footprints;  // seen from 8 azimuths
};
// An exemplar of a skeleton (up = +Z): its segments run from fork to fork
// (or tip), as the MRF's segments of a drawing do (the segments of Chen
// 2008 are the drawn branches between branchings).
TreeExemplar MakeExemplar(const std::string& name, const SkeletonGraph& skeleton);
// The exemplar whose footprint (over its azimuths) is nearest `footprint`;
// -1 if there are none.
int SelectTemplate(const std::vector<TreeExemplar>& exemplars, const Footprint& footprint);

struct MrfOptions {
  double interaction = 5.0;  // k_e, the branch interaction factor (paper: 5)
  int density_grid = 25;     // voxels per side of the branch density grid
  // The interaction kernel 1 / (1 + r^2) is summed over the voxels within
  // this many of the point's (its value 3 voxels away is a tenth of the
  // centre's); 0 = the whole grid, as the paper writes it (the benchmark's
  // reference).
  int crowding_reach = 2;
  int depth_candidates = 33;  // depths tried per node and step
  int max_icm_sweeps = 40;
  double icm_epsilon = 0.01;   // stop when sum |dz| < epsilon x tree size
  int em_iterations = 10;      // EM rounds over Omega (0: Omega fixed)
  double prior_weight = 10.0;  // exemplar relations Omega's prior counts as
  int generations = 5;         // propagation without a crown
  int max_segments = 1500;     // propagation stops at this many segments
  uint64_t seed = 1;
  void Check() const;  // throws InputError naming the option
};

// Where a crown lets branches grow: true inside.
using CrownTest = std::function<bool(const Eigen::Vector3d&)>;

// The crown of local revolution of a drawn outline (Okabe 2005, as section
// 6 uses it): at height h along `up`, the drawing spans [lo(h), hi(h)]
// across (as `spans` gives it, sampled every `step` from `bottom`); the 3D
// crown there is the disc about the span's middle with half its width as
// radius, in the plane of `across` and the line of sight.
struct CrownOfRevolution {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // a point at height 0, depth 0
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d across = Eigen::Vector3d::UnitX();
  double bottom = 0.0, step = 1.0;
  std::vector<std::pair<double, double>> spans;  // (lo, hi) across; lo > hi: empty
  // The crown's depth over its width (1: a surface of revolution).
  double depth_scale = 1.0;
  bool Contains(const Eigen::Vector3d& p) const;
  // Deepens the crown (depth_scale, at most `max_scale`) until it holds
  // every one of `points` that lies within its drawn span: the MRF may put
  // drawn branches deeper than a crown of revolution, and propagation starts
  // from their tips.
  void DeepenToHold(const std::vector<Eigen::Vector3d>& points, double max_scale);
};

struct MrfResult {
  SegmentTree tree;           // the drawn segments first (same indices), then propagated
  int drawn = 0;              // segments of the drawing
  TreeParameters parameters;  // Omega after EM
  int icm_sweeps = 0, em_iterations = 0;
  int template_idx = -1;
  int interpenetrations = 0;  // pushed apart after the bottom-up pass
};

// Infers the depths of a drawn tree. `drawn.points` lie on the drawing's
// plane (depth 0); depths are along `view_direction` (unit, across `up`).
// `template_parameters` is Omega's prior. Deterministic.
MrfResult InferBranchDepths(const SegmentTree& drawn, const Eigen::Vector3d& view_direction,
                            const TreeParameters& template_parameters, const MrfOptions& options);

// Adds self-similar propagation to `result` (section 6): blocks from the
// inferred tree (or from `fallback` when it has no fork), within `crown` if
// given, else options.generations generations. Deterministic by seed.
void PropagateBranches(const SegmentTree& fallback, const CrownTest& crown,
                       const MrfOptions& options, MrfResult* result);

// A segment tree as a skeleton (edges no longer than `max_edge`; radii 0,
// orders from SkeletonGraph::AssignOrders).
SkeletonGraph SkeletonOfSegments(const SegmentTree& tree, double max_edge);

}  // namespace sylva

#endif  // SYLVA_SKETCH_BRANCH_MRF_H_
