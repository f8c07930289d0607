// Tree structure metrics from a skeleton, as forest scientists report them
// (TreeQSM's treedata, ITSMe): height, crown size and volume, DBH, branch
// counts, lengths and angles per order, tips.
//
// Conventions: +Z is up and the base is the skeleton's root node. The
// tree's height is its top above the base: the highest skeleton node
// (SkeletonGraph::Height(), TreeQSM's TreeHeight for a QSM) or, with a
// density and a crown, the top of the density's crown envelope (below) if
// that is higher: the leaves above the last branch tip.
//
// Crown base height: the height above the base of the lowest point of the
// crown's major branches and their sub-branches, so a drooping branch
// lowers it (TreeQSM's CrownBaseHeight: the lowest start or end of the
// cylinders of the first major branch and its sub-branches). A first-order branch (an axis leaving
// the trunk axis, BranchAxes()[0]) is major when the branch length it carries (its own and its
// sub-branches', from the junction) is at least major_branch_fraction of what the largest
// first-order branch carries. So twigs leaving the trunk near the base (particle-flow skeletons
// make them) do not start the crown, however many there are, while the lowest of similar branches
// does. (TreeQSM 2.4 also asks a major branch to reach farther horizontally than the median
// first-order branch, which misses a near-vertical fork such as ITSMe tree 2's at 13.7 m: 28 % of
// the tree's length, 58 % of its DBH thick; sylva does not.) The crown is everything at or above
// the crown base; a skeleton without first-order branches has no crown (crown base = height, crown
// depth, width and volumes 0).
//
// Crown volume from the density: the volume of the crown region the
// density occupies above the crown base (mesh/crown_volume.h: the envelope
// of the density's support, gaps narrower than about 2 x
// crown_scale_fraction x the height closed; independent of the grid's
// resolution and of faint noise voxels).
//
// A branch is a branch axis, listed as SkeletonGraph::BranchAxes() lists them
// (trunk from the root, then breadth-first), except that an axis continues at
// every node into the child of lowest node `order` first, and never into a
// child of higher order than the node (then, as in BranchAxes(), most
// strands, thickest, lowest index), so the source's axes decide where it has
// them: TreeQSM's BranchOrder in a QSM, the generator's axes in a synthetic
// tree. For orders set by AssignOrders() (or all equal) these are exactly
// BranchAxes(). Other children start axes of the next order. A branch's
// length runs from its junction on the parent axis to its tip.
//
// Branching angle: between the branch's initial direction (from its first
// node after the junction to its first node at least direction_fraction of
// its length further; from the junction if the branch is one edge) and its
// parent axis' direction arriving at the junction over the same distance
// (leaving it, if the parent axis starts there). For a QSM this is the angle
// between the branch's first cylinder(s) and its parent cylinder(s).
//
// Measured or prior: every figure is labelled with where it comes from
// (TreeMetricsReport::sources): figures from node positions (height, crown
// base height, depth, width, hull volume) with SkeletonSources::positions,
// the density crown volume "measured" (the density is the photos'
// evidence), DBH with the skeleton's radius_source, and the figures that
// count or add up branches (tips, total length, everything per order) with
// SkeletonSources::branching. For sylva's reconstructions positions are
// "measured" (the skeleton follows the density reconstructed from the
// photos), the branching a "prior" (the particle count and merging decide
// how many branches there are and how long), the radii an "allometric
// prior".
#ifndef SYLVA_MESH_TREE_METRICS_H_
#define SYLVA_MESH_TREE_METRICS_H_

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"

namespace sylva {

struct TreeMetricsOptions {
  // Height of the DBH measurement above the base, in metres (converted to the
  // skeleton's units when they are "m", "cm" or "mm").
  double dbh_height_m = 1.3;
  // A first-order branch is major (may start the crown) when it carries at
  // least this fraction of the branch length the largest first-order
  // branch carries. In (0, 1].
  double major_branch_fraction = 0.1;
  // The density crown volume closes gaps narrower than about 2 x this
  // fraction x the tree's height (CrownVolumeOptions::scale; 3 %: 17 cm on
  // the 5.6 m demo tree). In [0, 1).
  double crown_scale_fraction = 0.03;
  // Density voxels fainter than this fraction of the crown's typical
  // extinction are noise (CrownVolumeOptions::support_fraction). In (0, 1].
  double density_support_fraction = 0.05;
  // A branch's initial direction runs from its junction to its first node at
  // least this fraction of the branch's length away (so a few-mm connector at
  // a QSM junction does not decide the angle); the parent axis' direction is
  // taken over the same distance back from the junction. In (0, 1].
  double direction_fraction = 0.1;

  void Check() const;  // throws InputError naming the option
};

// Labels of a figure's source (TreeMetricsReport::sources).
inline constexpr const char* kMeasured = "measured";
inline constexpr const char* kPrior = "prior";

// Where a skeleton's node positions and branching come from, for labelling
// the figures; the radii's source is SkeletonGraph::radius_source. Free
// text; sylva uses kMeasured, kPrior, "ground truth" and "unknown".
struct SkeletonSources {
  std::string positions = "unknown";
  std::string branching = "unknown";

  // A particle-flow reconstruction: positions measured, branching a prior.
  static SkeletonSources Reconstruction() { return {kMeasured, kPrior}; }
};

struct OrderMetrics {
  int order = 0;  // 0 = trunk
  int num_branches = 0;
  double total_length = 0.0;    // world units
  int num_angles = 0;           // branches with a measurable angle (order >= 1)
  double mean_angle_deg = 0.0;  // branching angle, degrees; 0 if none
  double median_angle_deg = 0.0;
};

struct TreeMetricsReport {
  std::string units;               // of every length; areas and volumes in units^2, ^3
  double height = 0.0;             // the tree's top above the base (see above)
  double crown_base_height = 0.0;  // lowest point of the major branches, above the base
  double crown_depth = 0.0;        // height - crown_base_height
  double crown_width = 0.0;        // largest horizontal distance between two crown nodes
  double crown_volume_hull = 0.0;  // convex hull of the crown's nodes
  // Volume of the crown region the density occupies (see the file comment);
  // absent without a grid.
  std::optional<double> crown_volume_density;
  // Diameter at breast height: 2 x the radius of the trunk edge crossing
  // dbh_height_m above the base (the radius of that QSM cylinder). Absent
  // when the units are not metric or the trunk does not reach that height;
  // dbh_note says why.
  std::optional<double> dbh;
  std::string dbh_note;
  int num_nodes = 0;
  int num_tips = 0;
  double total_length = 0.0;
  std::vector<OrderMetrics> orders;  // by order, 0 first
  // The skeleton's sources (radius_source, SkeletonSources) and, per
  // figure (the JSON names above; "orders" for everything per order), its
  // source label (see the file comment). Unlabelled figures: "unknown".
  std::string radius_source = "unknown";
  SkeletonSources skeleton_sources;
  std::vector<std::pair<std::string, std::string>> sources;  // (figure, label)
  std::string SourceOf(const std::string& figure) const;

  // The report as a JSON object: {"format": "sylva-tree-metrics", "version":
  // 2, "units", "volume_units" (units^3), "angle_units" ("degrees"), every
  // field above under its name, "orders": [{"order", "num_branches",
  // "total_length", "num_angles", "mean_angle_deg", "median_angle_deg"}],
  // "radius_source", "position_source", "branching_source", "sources":
  // {figure: label}, "source_meanings": {label: what it means}}; absent
  // values (no density grid, no DBH, no angle) are null. Version 2 changed
  // the meaning of crown_base_height (major branches, not the first fork)
  // and crown_volume_density (resolution-independent region) and added the
  // sources; version 1 files are still read.
  std::string ToJson() const;
};

// `density` (optional, may be null) in the skeleton's world frame and units;
// `units` the skeleton's units ("m", "cm", "mm", or anything else, e.g.
// "arbitrary"). Throws InputError for bad options, Error if the skeleton fails
// Check() or is empty.
// `sources` label the figures (default: "unknown").
TreeMetricsReport ComputeTreeMetrics(const SkeletonGraph& skeleton, const DensityGrid* density,
                                     const std::string& units,
                                     const TreeMetricsOptions& options = TreeMetricsOptions(),
                                     const SkeletonSources& sources = SkeletonSources());

// Writes report.ToJson() atomically.
void WriteTreeMetricsJson(const std::filesystem::path& path, const TreeMetricsReport& report);
// Reads a metrics.json of version 1 or 2 (version 1: no sources, all
// "unknown"). Throws InputError naming the file and key for a malformed or
// foreign file.
TreeMetricsReport ReadTreeMetricsJson(const std::filesystem::path& path);

// Volume of the convex hull of `points` (incremental hull, O(n h)); 0 for
// fewer than 4 points or points (nearly) on a plane.
double ConvexHullVolume(const std::vector<Eigen::Vector3d>& points);

}  // namespace sylva

#endif  // SYLVA_MESH_TREE_METRICS_H_
