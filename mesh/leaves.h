// Leaves (thesis 5.4, first version): quads hanging off the thin branches,
// placed in proportion to the density around them, turned towards the light
// by phototropism, and dropped where they project outside the mattes.
#ifndef SYLVA_MESH_LEAVES_H_
#define SYLVA_MESH_LEAVES_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

struct LeafOptions {
  // Leaves to place; -1 = none (leafless plants). 0 (the default) = as many
  // as the density's leaf area
  // implies: by Beer-Lambert with randomly oriented leaves (projection
  // factor G = 0.5), a voxel of side s and optical depth x (per voxel length)
  // holds a leaf area of x s^2 / G. Leaves are drawn in proportion to the
  // density until this many pass the branch-reach and matte tests (or
  // max_draws_factor times as many were drawn).
  int num_leaves = 0;
  // Upper bound on the automatic count.
  int max_leaves = 200000;
  double max_draws_factor = 3.0;
  // Leaf length in world units; 0 = leaf_length_fraction x tree height.
  double leaf_length = 0.0;
  double leaf_length_fraction = 0.012;
  // Leaf width / length.
  double leaf_aspect = 0.6;
  // A leaf must be within this many leaf lengths of a thin branch (the twig
  // that carries it); farther draws are dropped.
  double twig_reach = 4.0;
  // Branches at most this fraction of the trunk radius carry leaves.
  double thin_branch_radius_fraction = 0.35;
  // 0: random orientation about the leaf's axis; 1: the leaf's normal turned
  // as close as possible to the outward direction from the crown centre
  // (thesis: n_opt = (a - z) / |a - z|). Halfway by default: fully turned
  // leaves are seen edge-on at the crown's silhouette, and the leaf count
  // from the leaf area assumes orientations near random (G = 0.5); at 0.8
  // the synthetic trees' silhouettes lost 2-4 % IoU.
  double phototropism = 0.5;
  // A leaf whose projected footprint has a mean matte value below this in
  // any view that sees it is dropped (thesis: "projected to empty or very
  // sparse regions"); alpha.
  double matte_threshold = 0.1;
  uint64_t seed = 1;

  // Throws InputError("Leaves.<field>", ...).
  void Check() const;
};

struct LeafSummary {
  int64_t target = 0;  // leaves wanted (num_leaves or from the leaf area)
  int64_t drawn = 0;
  int64_t kept = 0;
  int64_t far_from_branches = 0;
  int64_t outside_mattes = 0;
  double leaf_length = 0.0;  // world units
  std::string BriefReport() const;
};

// `skeleton` needs radii; `mattes` are one per view of `views` (may be empty
// to skip the matte test). Material "leaves" (double-sided).
TriangleMesh GenerateLeaves(const SkeletonGraph& skeleton, const DensityGrid& density,
                            const ImageSet& views, const std::vector<FloatImage>& mattes,
                            const LeafOptions& options, LeafSummary* summary);

}  // namespace sylva

#endif  // SYLVA_MESH_LEAVES_H_
