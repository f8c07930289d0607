// The pixel-ray equations of the density system (thesis eq. 3.3), built by
// exact voxel traversal of each downsampled pixel's rays.
#ifndef SYLVA_RECONSTRUCT_DENSITY_RAY_SYSTEM_H_
#define SYLVA_RECONSTRUCT_DENSITY_RAY_SYSTEM_H_

#include <cstdint>
#include <vector>

#include "core/geometry/voxel_traversal.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "reconstruct/density/sparse_system.h"
#include "reconstruct/density/view_sampling.h"

namespace sylva {

struct RaySystem {
  SparseRows matrix;        // rows: pixels; columns: unknown voxels; values: l_i
  std::vector<double> rhs;  // -log(1 - alpha_pixel)
  int64_t num_unexplained_pixels = 0;
};

// Sums over a pixel's rays of (column, length in voxel units), merged per
// column and divided by the number of rays. `column_of_voxel` maps dense
// voxel indices of `block` to columns (-1: not an unknown).
void PixelRow(const ImageSet& image_set, int view_idx, const ViewSampling& sampling, int pixel_x,
              int pixel_y, const VoxelBlock& block, const std::vector<int32_t>& column_of_voxel,
              std::vector<std::pair<int32_t, float>>* row);

// One equation per downsampled pixel whose rays cross an unknown voxel.
// `downsampled_mattes[v]` has sampling[v]'s size. Each row and its
// right-hand side are scaled by max(1 - alpha, min_row_weight). Pixels whose alpha exceeds
// `foreground_alpha` but whose rays cross no unknown are counted as
// unexplained.
RaySystem BuildRaySystem(const ImageSet& image_set, const std::vector<ViewSampling>& sampling,
                         const std::vector<FloatImage>& downsampled_mattes, const VoxelBlock& block,
                         const std::vector<int32_t>& column_of_voxel, int64_t num_columns,
                         double max_pixel_opacity, double foreground_alpha, double min_row_weight,
                         const ProgressTask& progress);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_RAY_SYSTEM_H_
