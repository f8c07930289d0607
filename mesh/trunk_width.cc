#include "mesh/trunk_width.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "mesh/allometry.h"

namespace sylva {
namespace {

// Walk step along the image, in pixels.
constexpr double kStepPixels = 0.25;
// The trunk's axis in a view is the projection of the segment from a
// sample point up by this fraction of the tree height: the trunk is taken
// as vertical near its base, so any short segment gives its direction;
// 1 % stays within the trunk's base (the samples are at 3-9 %) and is a
// few pixels long where the tree is a few hundred (only the direction is
// used).
constexpr double kAxisProbeFraction = 0.01;

bool IsForeground(const FloatImage& matte, const Eigen::Vector2d& pixel, double threshold) {
  const int x = static_cast<int>(std::floor(pixel.x()));
  const int y = static_cast<int>(std::floor(pixel.y()));
  if (x < 0 || y < 0 || x >= matte.width() || y >= matte.height()) return false;
  return matte.at(x, y) >= threshold;
}

// Length in pixels of the foreground run through `center` along `direction`;
// -1 if `center` is background or the run reaches `max_pixels`.
double RunLength(const FloatImage& matte, const Eigen::Vector2d& center,
                 const Eigen::Vector2d& direction, double threshold, double max_pixels) {
  if (!IsForeground(matte, center, threshold)) return -1.0;
  double extent[2] = {0.0, 0.0};
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector2d step = (side == 0 ? 1.0 : -1.0) * kStepPixels * direction;
    Eigen::Vector2d p = center;
    while (IsForeground(matte, p + step, threshold)) {
      p += step;
      extent[side] += kStepPixels;
      if (extent[0] + extent[1] > max_pixels) return -1.0;
    }
  }
  return extent[0] + extent[1] + kStepPixels;
}

// The foreground point nearest to `center` along +-`direction`, at most
// `max_pixels` away; false if there is none.
bool NearestForeground(const FloatImage& matte, const Eigen::Vector2d& direction, double threshold,
                       double max_pixels, Eigen::Vector2d* center) {
  for (double offset = 0; offset <= max_pixels; offset += kStepPixels) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector2d p = *center + sign * offset * direction;
      if (IsForeground(matte, p, threshold)) {
        *center = p;
        return true;
      }
    }
  }
  return false;
}

// Where the trunk's width is measured: a point on its axis, the axis'
// direction there, and the base radius per unit of radius there (pipe model).
struct TrunkSection {
  Eigen::Vector3d point, direction;
  double base_factor = 1.0;
};

// The width across the trunk at `section` in each view that measures one
// (world units).
std::vector<double> SectionWidths(const ImageSet& views, const std::vector<FloatImage>& mattes,
                                  const TrunkSection& section, double tree_height,
                                  const TrunkWidthOptions& options) {
  std::vector<double> widths;
  for (int v = 0; v < views.NumViews(); ++v) {
    const View& view = views.views[v];
    const Camera& camera = views.CameraOf(view);
    const Eigen::Vector3d above =
        section.point + section.direction * kAxisProbeFraction * tree_height;
    const Eigen::Vector3d point_in_cam = view.cam_from_world * section.point;
    const Eigen::Vector3d above_in_cam = view.cam_from_world * above;
    if (!camera.IsInFront(point_in_cam) || !camera.IsInFront(above_in_cam)) continue;
    Eigen::Vector2d center = camera.ImgFromCam(point_in_cam);
    const Eigen::Vector2d axis = camera.ImgFromCam(above_in_cam) - center;
    if (axis.norm() < 1e-9) continue;  // looking along the trunk
    const Eigen::Vector2d across(-axis.y() / axis.norm(), axis.x() / axis.norm());
    const double world_per_pixel = camera.WorldPerPixel(point_in_cam);
    if (!NearestForeground(mattes[v], across, options.matte_threshold,
                           options.search_fraction * tree_height / world_per_pixel, &center)) {
      continue;
    }
    const double pixels = RunLength(mattes[v], center, across, options.matte_threshold,
                                    options.max_width_fraction * tree_height / world_per_pixel);
    if (pixels > 0) widths.push_back(pixels * world_per_pixel);
  }
  return widths;
}

TrunkWidth MeasureSections(const ImageSet& views, const std::vector<FloatImage>& mattes,
                           const std::vector<TrunkSection>& sections, double tree_height,
                           const TrunkWidthOptions& options) {
  SYLVA_CHECK(static_cast<int>(mattes.size()) == views.NumViews());
  SYLVA_CHECK(tree_height > 0);
  TrunkWidth result;
  const double min_views = std::max(1.0, options.min_view_share * views.NumViews());
  for (const TrunkSection& section : sections) {
    std::vector<double> widths = SectionWidths(views, mattes, section, tree_height, options);
    result.num_measurements += static_cast<int>(widths.size());
    if (widths.size() < min_views) continue;
    std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
    const double base_radius = 0.5 * widths[widths.size() / 2] * section.base_factor;
    if (result.radius == 0 || base_radius < result.radius) result.radius = base_radius;
  }
  return result;
}

}  // namespace

TrunkWidth MeasureTrunkWidth(const ImageSet& views, const std::vector<FloatImage>& mattes,
                             const SkeletonGraph& skeleton, double tree_height,
                             const TrunkWidthOptions& options) {
  std::vector<TrunkSection> sections;
  const int root = skeleton.RootIdx();
  if (root < 0) return MeasureSections(views, mattes, sections, tree_height, options);
  const BranchAxis trunk = skeleton.BranchAxes().front();
  const std::vector<double> strands = EffectivePipeStrands(skeleton);
  const double base_z = skeleton.nodes[root].position.z();
  size_t k = 1;
  for (double fraction : options.sample_heights) {
    const double z = base_z + fraction * tree_height;
    // The first trunk edge reaching height z.
    while (k < trunk.size() && skeleton.nodes[trunk[k]].position.z() < z) ++k;
    if (k >= trunk.size()) break;
    const Eigen::Vector3d& from = skeleton.nodes[trunk[k - 1]].position;
    const Eigen::Vector3d& to = skeleton.nodes[trunk[k]].position;
    const double share = strands[trunk[k]] / strands[root];
    if (strands[trunk[k]] < options.min_strand_share * strands[trunk[1]] ||
        (to - from).norm() <= 0) {
      break;
    }
    const double t =
        to.z() > from.z() ? std::clamp((z - from.z()) / (to.z() - from.z()), 0.0, 1.0) : 0.0;
    sections.push_back({from + t * (to - from), (to - from).normalized(),
                        std::pow(1.0 / share, 1.0 / options.diameter_exponent)});
  }
  return MeasureSections(views, mattes, sections, tree_height, options);
}

TrunkRadius ChooseTrunkRadius(const ImageSet& views, const std::vector<FloatImage>& mattes,
                              const SkeletonGraph& skeleton, double tree_height,
                              double given_radius, double fallback_fraction,
                              double diameter_exponent) {
  TrunkRadius trunk;
  if (given_radius > 0) {
    trunk.radius = given_radius;
    trunk.how = "given";
    return trunk;
  }
  TrunkWidthOptions options;
  options.diameter_exponent = diameter_exponent;
  const TrunkWidth width = MeasureTrunkWidth(views, mattes, skeleton, tree_height, options);
  if (width.radius > 0) {
    trunk.radius = width.radius;
    trunk.how = "measured in " + std::to_string(width.num_measurements) + " matte sections";
    return trunk;
  }
  std::ostringstream how;
  how << "not measurable in the mattes; " << fallback_fraction << " x height";
  trunk.radius = fallback_fraction * tree_height;
  trunk.how = how.str();
  return trunk;
}

}  // namespace sylva
