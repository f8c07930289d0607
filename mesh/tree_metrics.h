// Tree structure metrics from a skeleton, as forest scientists report them
// (TreeQSM's treedata, ITSMe): height, crown size and volume, DBH, branch
// counts, lengths and angles per order, tips.
//
// Conventions: +Z is up and the base is the skeleton's root node. The crown
// is everything at or above the crown base, the height of the trunk's first
// branching (the first node on the trunk axis, SkeletonGraph::BranchAxes()[0],
// with two or more children); a skeleton without branching has no crown
// (crown depth and volumes 0).
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
#ifndef SYLVA_MESH_TREE_METRICS_H_
#define SYLVA_MESH_TREE_METRICS_H_

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"

namespace sylva {

struct TreeMetricsOptions {
  // Height of the DBH measurement above the base, in metres (converted to the
  // skeleton's units when they are "m", "cm" or "mm").
  double dbh_height_m = 1.3;
  // A density voxel belongs to the crown volume at this opacity or more.
  double density_threshold = 0.5;
  // A branch's initial direction runs from its junction to its first node at
  // least this fraction of the branch's length away (so a few-mm connector at
  // a QSM junction does not decide the angle); the parent axis' direction is
  // taken over the same distance back from the junction. In (0, 1].
  double direction_fraction = 0.1;

  void Check() const;  // throws InputError naming the option
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
  double height = 0.0;             // highest node above the base
  double crown_base_height = 0.0;  // above the base
  double crown_depth = 0.0;        // height - crown_base_height
  double crown_width = 0.0;        // largest horizontal distance between two crown nodes
  double crown_volume_hull = 0.0;  // convex hull of the crown's nodes
  // Volume of the density voxels (>= threshold) in the crown; absent without a grid.
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

  // The report as a JSON object: {"format": "sylva-tree-metrics", "version":
  // 1, "units", "volume_units" (units^3), "angle_units" ("degrees"), every
  // field above under its name, "orders": [{"order", "num_branches",
  // "total_length", "num_angles", "mean_angle_deg", "median_angle_deg"}]};
  // absent values (no density grid, no DBH, no angle) are null.
  std::string ToJson() const;
};

// `density` (optional, may be null) in the skeleton's world frame and units;
// `units` the skeleton's units ("m", "cm", "mm", or anything else, e.g.
// "arbitrary"). Throws InputError for bad options, Error if the skeleton fails
// Check() or is empty.
TreeMetricsReport ComputeTreeMetrics(const SkeletonGraph& skeleton, const DensityGrid* density,
                                     const std::string& units,
                                     const TreeMetricsOptions& options = TreeMetricsOptions());

// Writes report.ToJson() atomically.
void WriteTreeMetricsJson(const std::filesystem::path& path, const TreeMetricsReport& report);

// Volume of the convex hull of `points` (incremental hull, O(n h)); 0 for
// fewer than 4 points or points (nearly) on a plane.
double ConvexHullVolume(const std::vector<Eigen::Vector3d>& points);

}  // namespace sylva

#endif  // SYLVA_MESH_TREE_METRICS_H_
