#include "reconstruct/density/ray_system.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {

void PixelRow(const ImageSet& image_set, int view_idx, const ViewSampling& sampling, int pixel_x,
              int pixel_y, const VoxelBlock& block, const std::vector<int32_t>& column_of_voxel,
              std::vector<std::pair<int32_t, float>>* row) {
  row->clear();
  const int n = sampling.rays_per_axis;
  const float weight = 1.0f / static_cast<float>(n * n * block.voxel_size);
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) {
      const Ray3d ray =
          image_set.RayThroughPixel(view_idx, sampling.RayPosition(pixel_x, pixel_y, a, b));
      TraverseVoxels(block, ray, [&](int64_t voxel, double length) {
        const int32_t column = column_of_voxel[voxel];
        if (column >= 0) row->emplace_back(column, static_cast<float>(length) * weight);
      });
    }
  }
  if (n == 1) return;
  // Merge the entries of voxels crossed by several of the pixel's rays.
  std::sort(row->begin(), row->end(),
            [](const auto& l, const auto& r) { return l.first < r.first; });
  size_t out = 0;
  for (size_t i = 0; i < row->size(); ++i) {
    if (out > 0 && (*row)[out - 1].first == (*row)[i].first) {
      (*row)[out - 1].second += (*row)[i].second;
    } else {
      (*row)[out++] = (*row)[i];
    }
  }
  row->resize(out);
}

namespace {

// The equations of one image row of one view.
struct RowChunk {
  std::vector<int64_t> lengths;
  std::vector<int32_t> cols;
  std::vector<float> values;
  std::vector<double> rhs;
  int64_t unexplained = 0;
};

void BuildChunk(const ImageSet& image_set, int view_idx, const ViewSampling& sampling,
                const FloatImage& matte, int pixel_y, const VoxelBlock& block,
                const std::vector<int32_t>& column_of_voxel, double max_pixel_opacity,
                double foreground_alpha, double min_row_weight, RowChunk* chunk) {
  std::vector<std::pair<int32_t, float>> row;
  for (int pixel_x = 0; pixel_x < sampling.width(); ++pixel_x) {
    PixelRow(image_set, view_idx, sampling, pixel_x, pixel_y, block, column_of_voxel, &row);
    const double alpha = matte.at(pixel_x, pixel_y);
    if (row.empty()) {
      chunk->unexplained += alpha > foreground_alpha;
      continue;
    }
    const double weight = std::max(1.0 - alpha, min_row_weight);
    chunk->lengths.push_back(static_cast<int64_t>(row.size()));
    for (const auto& [col, value] : row) {
      chunk->cols.push_back(col);
      chunk->values.push_back(static_cast<float>(value * weight));
    }
    chunk->rhs.push_back(-std::log(1.0 - std::min(alpha, max_pixel_opacity)) * weight);
  }
}

}  // namespace

RaySystem BuildRaySystem(const ImageSet& image_set, const std::vector<ViewSampling>& sampling,
                         const std::vector<FloatImage>& downsampled_mattes, const VoxelBlock& block,
                         const std::vector<int32_t>& column_of_voxel, int64_t num_columns,
                         double max_pixel_opacity, double foreground_alpha, double min_row_weight,
                         const ProgressTask& progress) {
  // One chunk per (view, downsampled image row), filled in parallel and
  // concatenated in order, so the system does not depend on scheduling.
  std::vector<std::pair<int, int>> chunk_keys;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    for (int y = 0; y < sampling[v].height(); ++y) chunk_keys.emplace_back(v, y);
  }
  std::vector<RowChunk> chunks(chunk_keys.size());
  tbb::parallel_for(size_t{0}, chunk_keys.size(), [&](size_t i) {
    progress.CheckCancelled();
    const auto [v, y] = chunk_keys[i];
    BuildChunk(image_set, v, sampling[v], downsampled_mattes[v], y, block, column_of_voxel,
               max_pixel_opacity, foreground_alpha, min_row_weight, &chunks[i]);
  });
  RaySystem system;
  system.matrix.num_cols = num_columns;
  size_t num_rows = 0, num_nonzeros = 0;
  for (const RowChunk& chunk : chunks) {
    num_rows += chunk.rhs.size();
    num_nonzeros += chunk.cols.size();
  }
  system.matrix.row_offsets.reserve(system.matrix.row_offsets.size() + num_rows);
  system.matrix.cols.reserve(num_nonzeros);
  system.matrix.values.reserve(num_nonzeros);
  system.rhs.reserve(num_rows);
  for (RowChunk& chunk : chunks) {
    for (int64_t length : chunk.lengths) {
      system.matrix.row_offsets.push_back(system.matrix.row_offsets.back() + length);
    }
    system.matrix.cols.insert(system.matrix.cols.end(), chunk.cols.begin(), chunk.cols.end());
    system.matrix.values.insert(system.matrix.values.end(), chunk.values.begin(),
                                chunk.values.end());
    system.rhs.insert(system.rhs.end(), chunk.rhs.begin(), chunk.rhs.end());
    system.num_unexplained_pixels += chunk.unexplained;
    chunk = RowChunk();
  }
  return system;
}

}  // namespace sylva
