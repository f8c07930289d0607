#include "mesh/trunk_width.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/check.h"

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

}  // namespace

TrunkWidth MeasureTrunkWidth(const ImageSet& views, const std::vector<FloatImage>& mattes,
                             const Eigen::Vector3d& base, double tree_height,
                             const TrunkWidthOptions& options) {
  SYLVA_CHECK(static_cast<int>(mattes.size()) == views.NumViews());
  SYLVA_CHECK(tree_height > 0);
  std::vector<double> widths;
  for (int v = 0; v < views.NumViews(); ++v) {
    const View& view = views.views[v];
    const Camera& camera = views.CameraOf(view);
    for (double fraction : options.sample_heights) {
      const Eigen::Vector3d point = base + Eigen::Vector3d::UnitZ() * fraction * tree_height;
      const Eigen::Vector3d above =
          point + Eigen::Vector3d::UnitZ() * kAxisProbeFraction * tree_height;
      const Eigen::Vector3d point_in_cam = view.cam_from_world * point;
      const Eigen::Vector3d above_in_cam = view.cam_from_world * above;
      if (!camera.IsInFront(point_in_cam) || !camera.IsInFront(above_in_cam)) continue;
      const Eigen::Vector2d center = camera.ImgFromCam(point_in_cam);
      const Eigen::Vector2d axis = camera.ImgFromCam(above_in_cam) - center;
      if (axis.norm() < 1e-9) continue;  // looking along the trunk
      const Eigen::Vector2d across(-axis.y() / axis.norm(), axis.x() / axis.norm());
      const double world_per_pixel = camera.WorldPerPixel(point_in_cam);
      const double pixels = RunLength(mattes[v], center, across, options.matte_threshold,
                                      options.max_width_fraction * tree_height / world_per_pixel);
      if (pixels > 0) widths.push_back(pixels * world_per_pixel);
    }
  }
  TrunkWidth result;
  result.num_measurements = static_cast<int>(widths.size());
  if (widths.empty()) return result;
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  result.radius = 0.5 * widths[widths.size() / 2];
  return result;
}

TrunkRadius ChooseTrunkRadius(const ImageSet& views, const std::vector<FloatImage>& mattes,
                              const Eigen::Vector3d& base, double tree_height, double given_radius,
                              double fallback_fraction) {
  TrunkRadius trunk;
  if (given_radius > 0) {
    trunk.radius = given_radius;
    trunk.how = "given";
    return trunk;
  }
  const TrunkWidth width = MeasureTrunkWidth(views, mattes, base, tree_height);
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
