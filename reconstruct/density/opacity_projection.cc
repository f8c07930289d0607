#include "reconstruct/density/opacity_projection.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace sylva {
namespace {

// Opacity 1 would be an infinite optical depth; stored opacities are capped
// just below it.
constexpr double kMaxStoredOpacity = 1.0 - 1e-6;

}  // namespace

OpacityProjector::OpacityProjector(const DensityGrid& grid) {
  block_.voxel_size = grid.voxel_size();
  Eigen::Vector3i lo, hi;
  if (!grid.ActiveIndexBounds(&lo, &hi)) return;
  block_.dims = hi - lo + Eigen::Vector3i::Ones();
  block_.lower_corner = grid.WorldFromIndex(lo.cast<double>() - Eigen::Vector3d::Constant(0.5));
  optical_depth_.assign(block_.NumVoxels(), 0.0f);
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    const double clamped = std::min<double>(alpha, kMaxStoredOpacity);
    optical_depth_[block_.LinearIndex(ijk - lo)] = static_cast<float>(-std::log(1.0 - clamped));
  });
}

FloatImage OpacityProjector::Render(const ImageSet& image_set, int view_idx,
                                    const ViewSampling& sampling) const {
  FloatImage image(sampling.width(), sampling.height(), 1);
  if (optical_depth_.empty()) return image;
  const int n = sampling.rays_per_axis;
  const double weight = 1.0 / (n * n * block_.voxel_size);
  tbb::parallel_for(0, sampling.height(), [&](int pixel_y) {
    for (int pixel_x = 0; pixel_x < sampling.width(); ++pixel_x) {
      double depth = 0.0;
      for (int b = 0; b < n; ++b) {
        for (int a = 0; a < n; ++a) {
          const Ray3d ray =
              image_set.RayThroughPixel(view_idx, sampling.RayPosition(pixel_x, pixel_y, a, b));
          TraverseVoxels(block_, ray, [&](int64_t voxel, double length) {
            depth += optical_depth_[voxel] * length;
          });
        }
      }
      image.at(pixel_x, pixel_y) = static_cast<float>(1.0 - std::exp(-depth * weight));
    }
  });
  return image;
}

}  // namespace sylva
