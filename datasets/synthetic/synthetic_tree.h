// A procedural deciduous tree with known skeleton, radii and mesh: the
// ground truth that every reconstruction stage is tested against.
//
// The tree stands at the origin, +Z up, in metres. A slightly curved trunk
// carries three levels of branches; each branch sprouts children along its
// length, spread around it by golden-angle phyllotaxis with jitter, at 30-60
// degrees to it, shorter and thinner than itself, and bends gently upward.
// Radii follow the pipe model: a node's radius^pipe_exponent is proportional
// to the branch length it carries (plus a share per tip), so radii shrink
// from the base to the tips and a child is never thicker than its parent.
// Every tip ends in a leaf cluster: an ellipsoid filled with small randomly
// oriented leaf quads, so the crown is a leafy, partly see-through volume with
// blobby silhouettes and some holes.
//
// With the defaults the tree is about 6-6.5 m tall (5.5-7.5 m over seeds),
// its crown 4.5-6 m wide, with ~1,200 skeleton nodes, ~560 leaf clusters,
// ~36,000 leaves and ~90,000 triangles; generation takes ~15 ms.
// The same options and seed give a bit-identical skeleton and mesh.
#ifndef SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_TREE_H_
#define SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_TREE_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

struct SyntheticTreeOptions {
  // --- Trunk ---
  // Length of the trunk's centre line from the base to its tip, in metres.
  double trunk_length = 5.0;
  // Trunk radius at the base, in metres; all other radii follow from it.
  double trunk_base_radius = 0.16;
  // Random bending of the trunk, in radians per sqrt(metre).
  double trunk_wobble = 0.06;
  // Where the lowest and highest main branches leave the trunk, as fractions
  // of the trunk length, 0 <= crown_base < crown_top <= 1.
  double crown_base = 0.3;
  double crown_top = 0.92;

  // --- Branching (index 0: branches on the trunk, 1: on those, 2: on those) ---
  // Number of child branches on each parent branch, per level (>= 0).
  std::array<int, 3> num_children = {13, 7, 5};
  // Child length as a fraction of its parent's length, per level, before the
  // crown-shape factor (longest at a third of the crown's height).
  std::array<double, 3> length_ratio = {0.6, 0.45, 0.5};
  // Children sit on [child_start, 1) of their parent's length (levels 1, 2);
  // on the trunk, within [crown_base, crown_top].
  double child_start = 0.2;
  // Angle between a child and its parent, uniform in [min, max], in degrees.
  double branch_angle_min_deg = 30.0;
  double branch_angle_max_deg = 60.0;
  // Rotation about the parent between successive children, in degrees (the
  // golden angle), plus uniform jitter in [-jitter, jitter].
  double phyllotaxis_angle_deg = 137.507764;
  double phyllotaxis_jitter_deg = 20.0;
  // Random bending of the branches, in radians per sqrt(metre).
  double branch_wobble = 0.15;
  // Upward bending of branches (trunk: towards vertical), in radians per
  // metre at most (scaled by how far the axis is from vertical).
  double upward_tropism = 0.2;
  // Skeleton edges are at most this long, in metres (> 0).
  double max_segment_length = 0.25;

  // --- Radii (pipe model) ---
  // radius^pipe_exponent is proportional to the carried length (> 0).
  double pipe_exponent = 2.0;
  // Length each tip counts as carrying beyond itself, in metres (> 0), so
  // tips keep a non-zero radius.
  double tip_length = 0.3;
  // Smallest radius of any node, in metres (> 0).
  double min_radius = 0.004;

  // --- Leaf clusters ---
  // Leaves per cluster (one cluster per tip), >= 0.
  int leaves_per_cluster = 64;
  // Cluster semi-axis across the tip's branch, in metres, times a uniform
  // random factor in [1 - cluster_size_jitter, 1 + cluster_size_jitter].
  double cluster_radius = 0.35;
  double cluster_size_jitter = 0.25;
  // Semi-axis along the tip's branch relative to the cross semi-axis (> 0).
  double cluster_elongation = 1.3;
  // Leaf length (tip to stalk), uniform in [min, max], in metres.
  double leaf_length_min = 0.05;
  double leaf_length_max = 0.10;
  // Leaf width / leaf length (> 0). Leaves are rhombi of this aspect.
  double leaf_aspect = 0.6;

  // --- Mesh ---
  // Branch tubes get ceil(2 pi r / tube_edge_length) sides, clamped to
  // [tube_min_sides, tube_max_sides]; in metres.
  double tube_edge_length = 0.03;
  int tube_min_sides = 3;
  int tube_max_sides = 24;
  // Linear RGB diffuse colours of the "bark" and "leaves" materials.
  Eigen::Vector3f bark_color = Eigen::Vector3f(0.36f, 0.26f, 0.18f);
  Eigen::Vector3f leaf_color = Eigen::Vector3f(0.22f, 0.46f, 0.13f);

  // Throws InputError naming the first violated constraint.
  void Check() const;
};

// The ellipsoid a tip's leaves fill: semi-axis `along` on `axis` (the tip
// edge's unit direction), `across` on the two directions perpendicular to it.
struct SyntheticLeafCluster {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // metres
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // unit
  double along = 0.0, across = 0.0;                  // semi-axes, metres

  bool Contains(const Eigen::Vector3d& point) const;
  double Volume() const;  // 4/3 pi along across^2
};

struct SyntheticTree {
  // Ground-truth skeleton: radii are exact (radius_source "ground truth"),
  // node order is the branch order (0 = trunk).
  SkeletonGraph skeleton;
  // Materials "bark" (closed tubes, one per skeleton edge) and "leaves"
  // (double-sided rhombi, two triangles each).
  TriangleMesh mesh;
  int num_leaves = 0;
  int num_clusters = 0;
  // Every leaf cluster's ellipsoid, in the order of their tips' node index
  // (the crown's true shape: the region its leaves fill is their union).
  std::vector<SyntheticLeafCluster> clusters;
};

SyntheticTree GenerateSyntheticTree(const SyntheticTreeOptions& options, uint64_t seed);

// The volume of the union of `clusters` (the region the crown's leaves
// fill), by Monte Carlo: `samples_per_cluster` points uniform in each
// cluster count when no earlier cluster holds them. Relative standard error
// about 1 / sqrt(samples_per_cluster x clusters); same seed, same value.
double LeafClustersUnionVolume(const std::vector<SyntheticLeafCluster>& clusters,
                               int samples_per_cluster, uint64_t seed);

// The pieces, for tests and other generators.
// The skeleton alone (same as GenerateSyntheticTree(options, seed).skeleton).
SkeletonGraph GenerateSyntheticSkeleton(const SyntheticTreeOptions& options, uint64_t seed);
// Closed tubes along every skeleton edge, appended to `mesh` with `material`.
void AddBranchTubes(const SkeletonGraph& skeleton, const SyntheticTreeOptions& options,
                    int material, TriangleMesh* mesh);

}  // namespace sylva

#endif  // SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_TREE_H_
