// Twigs (thesis 5.4): fine branches grown from the skeleton's terminal
// branches, more of them where the density is high, in a monopodial or a
// sympodial pattern (Deussen & Lintermann 2005, p. 14), bent by tropism
// against the twigs' stiffness.
//
// The photographs cannot show twigs (too thin, occluded), so their number is
// driven by the density grid and their look by a few species-like options.
// The result is the input skeleton with twig nodes appended, so the branch
// mesher sweeps them like any other branch:
//   - nodes 0 .. N-1 of the input keep their index, position, radius, order
//     and strands; only a parent_idx changes where a twig joins mid-edge
//     (the edge is split by an appended node of the same axis order);
//   - twig nodes are appended with order = TwigSummary::twig_order (one
//     more than the input's highest order), their side shoots (monopodial
//     laterals, sympodial spent apices) with twig_order + 1, and strands 0;
//     Select them with `node.order >= summary.twig_order`.
//
// Meshing the twigs. Joined (the pipeline's choice for few twigs), the
// grown skeleton is meshed as one watertight bark (closed; a twig that finds
// no room on its branch's tube stays a closed solid of its own, counted:
// mesh/bark_mesh.h), but the twigs multiply the bark's triangles (5.8x with ~800 twigs on a
// synthetic tree) and their many thin junctions slow the bark mesher down
// or, on dense trees, make it collapse the tree into one convex hull (see
// TwigMeshOptions::separate_above). Separate: the bark is
// the watertight mesh of RemoveTwigs(grown) (the branches, with the split
// nodes where the twigs start), and MeshTwigTubes gives each twig axis its
// own closed, capped tube in the material "twigs" (as MeshBranches does for
// every axis). The tubes' bases sit inside the bark and overlap it, so the
// tree is then a closed bark plus closed twig tubes, not one manifold.
#ifndef SYLVA_MESH_TWIGS_H_
#define SYLVA_MESH_TWIGS_H_

#include <cstdint>
#include <string>

#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "mesh/branch_mesh.h"

namespace sylva {

struct TwigOptions {
  // "monopodial": a straight leading twig axis with lateral shoots (spruce,
  // oak); "sympodial": a zig-zag of short units, each continued by a
  // lateral bud while its spent apex stays as a stub (monochasium, linden).
  std::string pattern = "monopodial";
  // Twigs per twig length of terminal branch where the density equals the
  // mean opacity of the grid's active voxels; proportional to the opacity
  // elsewhere (up to max_density_factor times), none where it is empty. An
  // empty grid means "no density information": the rate is used as is.
  double twigs_per_length = 1.5;
  double max_density_factor = 2.0;
  // Twig length, world units; 0 = length_fraction x tree height. Each twig
  // varies by a uniform factor in [1 - length_variation, 1 + length_variation].
  double length = 0.0;
  double length_fraction = 0.04;
  double length_variation = 0.3;
  // Angle between a twig and its parent branch, degrees (0, 180).
  double branching_angle_deg = 45.0;
  // Pipe-model radius (thesis 5.1): a twig carries this fraction of the
  // strands of its parent branch's tip, so its base radius is
  // r_tip x fraction^(1 / diameter_exponent); it tapers linearly to
  // tip_taper x that at its end.
  double strand_fraction = 0.25;
  double diameter_exponent = 2.0;
  double tip_taper = 0.5;
  // Tropism: each segment's direction is pulled towards +Z (> 0: shoots
  // bending up) or -Z (< 0: drooping under their weight) by
  // |tropism| x (1 - stiffness) x (segment / segments), so a twig bends
  // most towards its end, as a loaded cantilever does. Ranges [-1, 1], [0, 1].
  double tropism = 0.2;
  double stiffness = 0.5;
  // Edges per twig (the twig's nodes beyond its base).
  int segments = 4;
  // Monopodial: lateral shoots per twig, half as long, alternating sides.
  int laterals = 2;
  // Sympodial: turn of each unit from the previous one, degrees, alternating.
  double sympodial_angle_deg = 30.0;
  uint64_t seed = 1;

  // Throws InputError("Twigs.<field>", ...).
  void Check() const;
};

struct TwigSummary {
  int terminal_branches = 0;  // branch axes that carry twigs
  int twigs = 0;
  int nodes_added = 0;        // split nodes + twig nodes
  int first_added_node = 0;   // index of the first appended node
  int twig_order = 0;         // order of twig nodes (side shoots: + 1)
  double twig_length = 0.0;   // world units, before variation
  double total_length = 0.0;  // of all twig edges, world units
  std::string BriefReport() const;
};

// Terminal branches: branch axes (SkeletonGraph::BranchAxes) from which no
// other axis starts. `skeleton` needs radii. Deterministic for a seed.
SkeletonGraph GrowTwigs(const SkeletonGraph& skeleton, const DensityGrid& density,
                        const TwigOptions& options, TwigSummary* summary = nullptr);

// How the twigs are meshed (see the header comment).
struct TwigMeshOptions {
  // "joined": part of the bark mesh; "separate": closed tubes of their own
  // beside the bark; "auto": separate when a tree has more than
  // separate_above twigs.
  std::string mode = "auto";
  // Twigs above which "auto" meshes them separately (>= 0). Measured on the
  // default synthetic trees, seeds 1-3 (tests/bench/twig_mesh_benchmark.cc):
  // joined, the bark stays right up to ~220 twigs (1.4-8x the separate
  // time, 2.4x the bare bark's triangles), but from 367 twigs (seed 2) and
  // at the default rate (740-810 twigs, seeds 2 and 3) the watertight mesher
  // collapses the tree into a 220-440 triangle hull after 14-225 s, while
  // the separate bark stays closed in < 0.5 s.
  int separate_above = 200;
  // The twig tubes' material (single-sided: the tubes are closed).
  Material material = {"twigs", Eigen::Vector3f(0.45f, 0.35f, 0.22f), false};

  // Whether a tree with `twigs` twigs gets separate twig tubes.
  bool Separate(int twigs) const;
  // Throws InputError("Twigs.mesh" / "Twigs.separate_above", ...).
  void Check() const;
};

struct TwigTubesSummary {
  int tubes = 0;  // one per twig axis (twig, lateral shoot or spent apex)
  int triangles = 0;
  double seconds = 0.0;
  std::string BriefReport() const;
};

// `grown` (from GrowTwigs, with its `summary`) without the twig nodes: the
// input skeleton plus the split nodes on the terminal branches, which lie on
// the branch edges they split, so that the branches' splines pass through
// the twigs' bases. Nodes below summary.first_added_node keep their index,
// the kept split nodes follow in their order.
SkeletonGraph RemoveTwigs(const SkeletonGraph& grown, const TwigSummary& summary);

// One closed tube per twig axis of `grown`: every BranchAxes() axis from its
// last node before the twig nodes (the split node or twig node it leaves)
// to its tip, planned and swept like MeshBranches' laterals (PlanAxisTube,
// sides relative to the largest radius in `grown`, `tube` options), capped
// at both ends, all in options.material. `summary` (may be null) gets the
// counts. Throws InputError for bad options, or a skeleton failing Check().
TriangleMesh MeshTwigTubes(const SkeletonGraph& grown, const TwigSummary& twigs,
                           const BranchMeshOptions& tube, const TwigMeshOptions& options,
                           TwigTubesSummary* summary = nullptr);

}  // namespace sylva

#endif  // SYLVA_MESH_TWIGS_H_
