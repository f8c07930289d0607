// The trunk's radius measured in the mattes, to scale the allometric radii
// (thesis 5.1 gives ratios, not sizes): at several heights along the trunk,
// the width of the foreground run crossing the projected trunk axis, in
// pixels, converted to world units at the trunk's depth; per height the
// median over views, turned into the base radius it implies by the pipe
// model (the trunk's share of the strands there); the smallest of these.
// Whatever stands beside a trunk near the ground (a pot, a stake and its
// clips, a tripod, grass) only widens the runs where it is, so the heights
// above it give the trunk; on the ROMI photos (an Arabidopsis staked in a
// pot) the median over the lowest heights measured the pot, 13 x the stem.
#ifndef SYLVA_MESH_TRUNK_WIDTH_H_
#define SYLVA_MESH_TRUNK_WIDTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"

namespace sylva {

struct TrunkWidthOptions {
  // Heights above the base where the width is measured, as fractions of the
  // tree height.
  std::vector<double> sample_heights = {0.03, 0.06, 0.09, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5};
  // A height counts when at least this share of the views measured a width
  // there (the others: trunk hidden or beside clutter up to the limit).
  double min_view_share = 0.5;
  // Along a skeleton's trunk, heights where the trunk carries less than this
  // share of the strands it starts with (above its main forks) are not
  // measured.
  double min_strand_share = 0.5;
  // The pipe model's exponent (Allometry.diameter_exponent) that turns a
  // width up the trunk into the base's.
  double diameter_exponent = 2.0;
  // A pixel belongs to the trunk at this alpha or more.
  double matte_threshold = 0.5;
  // The trunk's axis (a skeleton's: as exact as the density's voxels) may
  // miss a thin stem in a view: the run measured is the nearest one across
  // the axis within this fraction of the tree height.
  double search_fraction = 0.01;
  // Runs wider than this fraction of the tree height are not a trunk
  // (foliage reaching the ground, a pot, the ground) and are ignored.
  double max_width_fraction = 0.2;
};

struct TrunkWidth {
  double radius = 0.0;       // world units; 0 if not measurable
  int num_measurements = 0;  // (view, height) pairs that gave a width
};

// Along the trunk axis of `skeleton` (its strands give each height's share;
// +Z is up, sylva's world frame); `tree_height` in world units.
TrunkWidth MeasureTrunkWidth(const ImageSet& views, const std::vector<FloatImage>& mattes,
                             const SkeletonGraph& skeleton, double tree_height,
                             const TrunkWidthOptions& options = TrunkWidthOptions());

// The trunk radius that scales the allometric radii, and how it was found.
struct TrunkRadius {
  double radius = 0.0;  // world units
  std::string how;      // "given", "measured in N matte sections" or the fallback
};

// `given_radius` if > 0 (Skeleton.trunk_radius), else measured in the
// mattes along `skeleton`'s trunk (MeasureTrunkWidth with the default
// options and `diameter_exponent`), else `fallback_fraction` x
// `tree_height` (Skeleton.trunk_radius_fraction: no mattes, or no trunk
// visible in them).
TrunkRadius ChooseTrunkRadius(const ImageSet& views, const std::vector<FloatImage>& mattes,
                              const SkeletonGraph& skeleton, double tree_height,
                              double given_radius, double fallback_fraction,
                              double diameter_exponent);

}  // namespace sylva

#endif  // SYLVA_MESH_TRUNK_WIDTH_H_
