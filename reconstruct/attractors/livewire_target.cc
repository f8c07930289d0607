#include "reconstruct/attractors/livewire_target.h"

#include <cmath>
#include <limits>

#include "core/util/check.h"

namespace sylva {

Eigen::Vector2d NearestForeground(const FloatImage& matte, const Eigen::Vector2d& point_in_image,
                                  double threshold) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d nearest = point_in_image;
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      if (matte.at(x, y, 0) < threshold) continue;
      const Eigen::Vector2d centre(x + 0.5, y + 0.5);
      const double d2 = (centre - point_in_image).squaredNorm();
      if (d2 < best) best = d2, nearest = centre;
    }
  }
  SYLVA_CHECK_INPUT(std::isfinite(best), "matte") << "the matte has no foreground pixel";
  return nearest;
}

LivewireTarget ChooseLivewireTarget(const ImageSet& views, int view_idx,
                                    const Eigen::Vector3d& base_in_world, const FloatImage& matte,
                                    double matte_threshold) {
  LivewireTarget target;
  if (!views.Project(view_idx, base_in_world, &target.point_in_image)) {
    target.note = "tree base behind the camera";
    return target;
  }
  target.found = true;
  const Camera& camera = views.CameraOf(view_idx);
  const Eigen::Vector2d& p = target.point_in_image;
  if (p.x() >= 0 && p.y() >= 0 && p.x() <= camera.width() && p.y() <= camera.height()) {
    return target;
  }
  target.point_in_image = NearestForeground(matte, p, matte_threshold);
  target.note = "tree base outside the photo; target moved to the matte's nearest point";
  return target;
}

}  // namespace sylva
