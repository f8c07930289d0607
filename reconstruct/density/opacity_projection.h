// Renders a density grid's opacity as seen from a view: the forward model of
// the density system (1 - exp(-sum of optical depth x length) along exact
// voxel traversals), used for fidelity reports and tests. Rays step over
// empty bricks of 8^3 voxels and traverse the voxels of the others.
#ifndef SYLVA_RECONSTRUCT_DENSITY_OPACITY_PROJECTION_H_
#define SYLVA_RECONSTRUCT_DENSITY_OPACITY_PROJECTION_H_

#include <vector>

#include "core/geometry/voxel_traversal.h"
#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "reconstruct/density/view_sampling.h"

namespace sylva {

class OpacityProjector {
 public:
  // Copies the grid's active voxels into dense bricks of optical depths.
  explicit OpacityProjector(const DensityGrid& grid);

  // Opacity per downsampled pixel of `sampling`: each pixel's rays are
  // averaged in log-transparency, as in the density system.
  FloatImage Render(const ImageSet& image_set, int view_idx, const ViewSampling& sampling) const;

  // Dense block covering the grid's active voxels (empty if none).
  const VoxelBlock& block() const { return block_; }
  Eigen::Vector3d Center() const {
    return block_.lower_corner + 0.5 * block_.voxel_size * block_.dims.cast<double>();
  }

 private:
  // The voxels of brick `brick` of bricks_ as a block of its own (the last
  // bricks along an axis may be partial).
  VoxelBlock BrickBlock(int64_t brick) const;
  // Optical depth through the block along `ray` (per voxel length x length).
  double OpticalDepth(const Ray3d& ray) const;

  VoxelBlock block_;
  VoxelBlock bricks_;                 // block_ cut in bricks of kBrickSize^3 voxels
  std::vector<int64_t> brick_start_;  // per brick: its first value in optical_depth_, -1 if empty
  std::vector<float> optical_depth_;  // per voxel of the occupied bricks, per voxel length
};

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_OPACITY_PROJECTION_H_
