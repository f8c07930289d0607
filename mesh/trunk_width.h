// The trunk's radius measured in the mattes, to scale the allometric radii
// (thesis 5.1 gives ratios, not sizes): at a few heights just above the base,
// the width of the foreground run crossing the projected trunk axis, in
// pixels, converted to world units at the trunk's depth; the median over
// views and heights.
#ifndef SYLVA_MESH_TRUNK_WIDTH_H_
#define SYLVA_MESH_TRUNK_WIDTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"

namespace sylva {

struct TrunkWidthOptions {
  // Heights above the base where the width is measured, as fractions of the
  // tree height.
  std::vector<double> sample_heights = {0.03, 0.06, 0.09};
  // A pixel belongs to the trunk at this alpha or more.
  double matte_threshold = 0.5;
  // Runs wider than this fraction of the tree height are not a trunk
  // (foliage reaching the ground, a pot, the ground) and are ignored.
  double max_width_fraction = 0.2;
};

struct TrunkWidth {
  double radius = 0.0;       // world units; 0 if not measurable
  int num_measurements = 0;  // (view, height) pairs that gave a width
};

// `base` is the bottom of the trunk and +Z is up (sylva's world frame);
// `tree_height` in world units.
TrunkWidth MeasureTrunkWidth(const ImageSet& views, const std::vector<FloatImage>& mattes,
                             const Eigen::Vector3d& base, double tree_height,
                             const TrunkWidthOptions& options = TrunkWidthOptions());

// The trunk radius that scales the allometric radii, and how it was found.
struct TrunkRadius {
  double radius = 0.0;  // world units
  std::string how;      // "given", "measured in N matte sections" or the fallback
};

// `given_radius` if > 0 (Skeleton.trunk_radius), else measured in the
// mattes (MeasureTrunkWidth with the default options), else
// `fallback_fraction` x `tree_height` (Skeleton.trunk_radius_fraction: no
// mattes, or no trunk visible in them).
TrunkRadius ChooseTrunkRadius(const ImageSet& views, const std::vector<FloatImage>& mattes,
                              const Eigen::Vector3d& base, double tree_height, double given_radius,
                              double fallback_fraction);

}  // namespace sylva

#endif  // SYLVA_MESH_TRUNK_WIDTH_H_
