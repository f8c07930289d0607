#include "reconstruct/density/opacity_projection.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace sylva {
namespace {

// Opacity 1 would be an infinite optical depth; stored opacities are capped
// just below it.
constexpr double kMaxStoredOpacity = 1.0 - 1e-6;
// Voxels per brick edge.
constexpr int kBrickSize = 8;

}  // namespace

OpacityProjector::OpacityProjector(const DensityGrid& grid) {
  block_.voxel_size = grid.voxel_size();
  Eigen::Vector3i lo, hi;
  if (!grid.ActiveIndexBounds(&lo, &hi)) return;
  block_.dims = hi - lo + Eigen::Vector3i::Ones();
  block_.lower_corner = grid.WorldFromIndex(lo.cast<double>() - Eigen::Vector3d::Constant(0.5));
  bricks_.lower_corner = block_.lower_corner;
  bricks_.voxel_size = kBrickSize * block_.voxel_size;
  bricks_.dims = (block_.dims.array() + kBrickSize - 1) / kBrickSize;
  // Bricks holding a voxel of non-zero depth get storage, in brick order.
  brick_start_.assign(bricks_.NumVoxels(), -1);
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    if (alpha > 0.0f) brick_start_[bricks_.LinearIndex((ijk - lo) / kBrickSize)] = 0;
  });
  int64_t size = 0;
  for (int64_t b = 0; b < bricks_.NumVoxels(); ++b) {
    if (brick_start_[b] < 0) continue;
    brick_start_[b] = size;
    size += BrickBlock(b).NumVoxels();
  }
  optical_depth_.assign(size, 0.0f);
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    if (!(alpha > 0.0f)) return;
    const Eigen::Vector3i local = ijk - lo;
    const int64_t brick = bricks_.LinearIndex(local / kBrickSize);
    const VoxelBlock voxels = BrickBlock(brick);
    const double clamped = std::min<double>(alpha, kMaxStoredOpacity);
    optical_depth_[brick_start_[brick] +
                   voxels.LinearIndex(local - (local / kBrickSize) * kBrickSize)] =
        static_cast<float>(-std::log(1.0 - clamped));
  });
}

VoxelBlock OpacityProjector::BrickBlock(int64_t brick) const {
  const Eigen::Vector3i first = bricks_.VoxelFromLinear(brick) * kBrickSize;
  VoxelBlock voxels;
  voxels.voxel_size = block_.voxel_size;
  voxels.lower_corner = block_.lower_corner + block_.voxel_size * first.cast<double>();
  voxels.dims = (block_.dims - first).cwiseMin(kBrickSize);
  return voxels;
}

double OpacityProjector::OpticalDepth(const Ray3d& ray) const {
  double depth = 0.0;
  TraverseVoxels(bricks_, ray, [&](int64_t brick, double) {
    const int64_t start = brick_start_[brick];
    if (start < 0) return;
    TraverseVoxels(BrickBlock(brick), ray, [&](int64_t voxel, double length) {
      depth += optical_depth_[start + voxel] * length;
    });
  });
  return depth;
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
          depth += OpticalDepth(ray);
        }
      }
      image.at(pixel_x, pixel_y) = static_cast<float>(1.0 - std::exp(-depth * weight));
    }
  });
  return image;
}

}  // namespace sylva
