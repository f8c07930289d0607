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

// Edge, in voxels, of the cells of ReachablePixels.
constexpr int kCellVoxels = 4;

// Calls f(lower corner, edge) (world units) for every cell of kCellVoxels^3
// voxels of `block` that holds an unknown, in order, until f returns false;
// false if it did.
template <typename F>
bool ForEachOccupiedCell(const VoxelBlock& block, const std::vector<char>& occupied_cells,
                         const Eigen::Vector3i& cell_dims, F&& f) {
  const double cell_size = kCellVoxels * block.voxel_size;
  for (int z = 0; z < cell_dims.z(); ++z) {
    for (int y = 0; y < cell_dims.y(); ++y) {
      for (int x = 0; x < cell_dims.x(); ++x) {
        if (occupied_cells[(static_cast<size_t>(z) * cell_dims.y() + y) * cell_dims.x() + x] &&
            !f(Eigen::Vector3d(block.lower_corner + cell_size * Eigen::Vector3d(x, y, z)),
               cell_size)) {
          return false;
        }
      }
    }
  }
  return true;
}

// A pixel's rays through a camera with lens distortion pass through the
// normalized (undistorted, z = 1) points of its block of the image; those
// lie in the rectangle around its corners' points widened by this share of
// its size (the distortion is nearly affine over a pixel).
constexpr double kPixelRectSlack = 0.1;

// ReachablePixels (below) for a perspective camera with lens distortion,
// whose image of a box may bulge past its corners' rectangle: in the
// normalized plane instead. A ray meets a cell only if its normalized point
// lies in the rectangle of the cell's corners' normalized points; those
// rectangles are marked (one grid cell wider on each side) on a grid over
// the pixels' normalized points, and a pixel is marked when its rectangle
// meets a marked grid cell. False (nothing marked) if a cell's corner is
// behind the camera.
bool MarkDistortedPixels(const ImageSet& image_set, int view_idx, const ViewSampling& sampling,
                         const VoxelBlock& block, const std::vector<char>& occupied_cells,
                         const Eigen::Vector3i& cell_dims, std::vector<char>* marked) {
  const int width = sampling.width(), height = sampling.height();
  const Camera& camera = image_set.CameraOf(view_idx);
  // The normalized points of the pixels' corners.
  const auto corner_position = [&](int i, int original) {
    return static_cast<double>(std::min(i * sampling.factor, original));
  };
  std::vector<Eigen::Vector2d> corners(static_cast<size_t>(width + 1) * (height + 1));
  Eigen::AlignedBox2d extent;
  for (int j = 0; j <= height; ++j) {
    for (int i = 0; i <= width; ++i) {
      const Eigen::Vector2d point =
          camera.CamFromImg(Eigen::Vector2d(corner_position(i, sampling.original_width),
                                            corner_position(j, sampling.original_height)));
      corners[static_cast<size_t>(j) * (width + 1) + i] = point;
      extent.extend(point);
    }
  }
  // The grid: as many cells as pixels, over the points' extent.
  const Eigen::Vector2d cell = extent.sizes().cwiseQuotient(Eigen::Vector2d(width, height));
  if (!(cell.x() > 0 && cell.y() > 0)) return true;
  const auto grid_of = [&](const Eigen::Vector2d& point, int offset) {
    const Eigen::Vector2d g = (point - extent.min()).cwiseQuotient(cell);
    return Eigen::Vector2i(
        static_cast<int>(std::clamp(std::floor(g.x()) + offset, 0.0, width - 1.0)),
        static_cast<int>(std::clamp(std::floor(g.y()) + offset, 0.0, height - 1.0)));
  };
  // Summed counts of marked grid cells, one row and column of zeros first.
  std::vector<int32_t> sums(static_cast<size_t>(width + 1) * (height + 1), 0);
  const auto sum_at = [&](int x, int y) -> int32_t& {
    return sums[static_cast<size_t>(y) * (width + 1) + x];
  };
  const Eigen::Matrix3d rotation =
      image_set.views[view_idx].cam_from_world.rotation.toRotationMatrix();
  const Eigen::Vector3d& translation = image_set.views[view_idx].cam_from_world.translation;
  const bool in_front = ForEachOccupiedCell(
      block, occupied_cells, cell_dims, [&](const Eigen::Vector3d& lower, double size) {
        Eigen::AlignedBox2d rect;
        for (int corner = 0; corner < 8; ++corner) {
          const Eigen::Vector3d offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
          const Eigen::Vector3d in_cam = rotation * (lower + size * offset) + translation;
          if (!camera.IsInFront(in_cam)) return false;
          rect.extend(Eigen::Vector2d(in_cam.head<2>() / in_cam.z()));
        }
        if (!rect.intersects(extent)) return true;
        const Eigen::Vector2i lo = grid_of(rect.min(), -1), hi = grid_of(rect.max(), 1);
        for (int gy = lo.y(); gy <= hi.y(); ++gy) {
          for (int gx = lo.x(); gx <= hi.x(); ++gx) sum_at(gx + 1, gy + 1) = 1;
        }
        return true;
      });
  if (!in_front) return false;
  for (int gy = 1; gy <= height; ++gy) {
    for (int gx = 1; gx <= width; ++gx) {
      sum_at(gx, gy) += sum_at(gx - 1, gy) + sum_at(gx, gy - 1) - sum_at(gx - 1, gy - 1);
    }
  }
  for (int py = 0; py < height; ++py) {
    for (int px = 0; px < width; ++px) {
      Eigen::AlignedBox2d rect;
      for (int k = 0; k < 4; ++k) {
        rect.extend(corners[static_cast<size_t>(py + (k >> 1)) * (width + 1) + px + (k & 1)]);
      }
      const Eigen::Vector2d slack = kPixelRectSlack * rect.sizes();
      const Eigen::Vector2i lo = grid_of(rect.min() - slack, 0);
      const Eigen::Vector2i hi = grid_of(rect.max() + slack, 0);
      const int32_t count = sum_at(hi.x() + 1, hi.y() + 1) - sum_at(lo.x(), hi.y() + 1) -
                            sum_at(hi.x() + 1, lo.y()) + sum_at(lo.x(), lo.y());
      (*marked)[static_cast<size_t>(py) * width + px] = count > 0;
    }
  }
  return true;
}

// Per downsampled pixel of a view: whether its rays may cross an unknown
// voxel. Each cell of kCellVoxels^3 voxels holding an unknown marks the
// pixels that meet the bounding rectangle of its 8 projected corners, one
// pixel wider on each side; a pinhole's (or an orthographic camera's) image
// of a box lies inside that rectangle, so a pixel left unmarked has no ray
// through an unknown, and its row would be empty. With lens distortion
// (its image of a box may bulge past the corners' rectangle), the same in
// the normalized plane (MarkDistortedPixels). Behind the camera, every
// pixel is marked.
std::vector<char> ReachablePixels(const ImageSet& image_set, int view_idx,
                                  const ViewSampling& sampling, const VoxelBlock& block,
                                  const std::vector<char>& occupied_cells,
                                  const Eigen::Vector3i& cell_dims) {
  const int width = sampling.width(), height = sampling.height();
  std::vector<char> marked(static_cast<size_t>(width) * height, 0);
  const Camera& camera = image_set.CameraOf(view_idx);
  if (camera.HasDistortion()) {
    if (camera.IsOrthographic() || !MarkDistortedPixels(image_set, view_idx, sampling, block,
                                                        occupied_cells, cell_dims, &marked)) {
      std::fill(marked.begin(), marked.end(), 1);
    }
    return marked;
  }
  const ViewProjector projector(image_set, view_idx);
  // Downsampled pixels, clamped before the conversion (a corner just in
  // front of a pinhole projects arbitrarily far out).
  const auto pixel_of = [&](double coordinate, int size) {
    return static_cast<int>(std::clamp(std::floor(coordinate / sampling.factor), -2.0, size + 1.0));
  };
  const bool in_front = ForEachOccupiedCell(
      block, occupied_cells, cell_dims, [&](const Eigen::Vector3d& lower, double size) {
        Eigen::AlignedBox2d rect;
        if (!projector.ProjectCube(lower, size, &rect)) return false;
        const int x0 = std::max(0, pixel_of(rect.min().x(), width) - 1);
        const int y0 = std::max(0, pixel_of(rect.min().y(), height) - 1);
        const int x1 = std::min(width - 1, pixel_of(rect.max().x(), width) + 1);
        const int y1 = std::min(height - 1, pixel_of(rect.max().y(), height) + 1);
        for (int py = y0; py <= y1; ++py) {
          std::fill(marked.begin() + static_cast<size_t>(py) * width + x0,
                    marked.begin() + static_cast<size_t>(py) * width + std::max(x0, x1 + 1), 1);
        }
        return true;
      });
  if (!in_front) std::fill(marked.begin(), marked.end(), 1);
  return marked;
}

// Cells of kCellVoxels^3 voxels of `block` that hold an unknown.
std::vector<char> OccupiedCells(const VoxelBlock& block,
                                const std::vector<int32_t>& column_of_voxel,
                                Eigen::Vector3i* cell_dims) {
  *cell_dims = (block.dims.array() + kCellVoxels - 1) / kCellVoxels;
  std::vector<char> occupied(static_cast<size_t>(cell_dims->prod()), 0);
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    if (column_of_voxel[i] < 0) continue;
    const Eigen::Vector3i cell = block.VoxelFromLinear(i) / kCellVoxels;
    occupied[(static_cast<size_t>(cell.z()) * cell_dims->y() + cell.y()) * cell_dims->x() +
             cell.x()] = 1;
  }
  return occupied;
}

void BuildChunk(const ImageSet& image_set, int view_idx, const ViewSampling& sampling,
                const FloatImage& matte, const std::vector<char>& reachable, int pixel_y,
                const VoxelBlock& block, const std::vector<int32_t>& column_of_voxel,
                double max_pixel_opacity, double foreground_alpha, double min_row_weight,
                RowChunk* chunk) {
  std::vector<std::pair<int32_t, float>> row;
  for (int pixel_x = 0; pixel_x < sampling.width(); ++pixel_x) {
    row.clear();
    if (reachable[static_cast<size_t>(pixel_y) * sampling.width() + pixel_x]) {
      PixelRow(image_set, view_idx, sampling, pixel_x, pixel_y, block, column_of_voxel, &row);
    }
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
  Eigen::Vector3i cell_dims;
  const std::vector<char> occupied_cells = OccupiedCells(block, column_of_voxel, &cell_dims);
  std::vector<std::vector<char>> reachable(image_set.NumViews());
  tbb::parallel_for(0, image_set.NumViews(), [&](int v) {
    reachable[v] = ReachablePixels(image_set, v, sampling[v], block, occupied_cells, cell_dims);
  });
  std::vector<RowChunk> chunks(chunk_keys.size());
  tbb::parallel_for(size_t{0}, chunk_keys.size(), [&](size_t i) {
    progress.CheckCancelled();
    const auto [v, y] = chunk_keys[i];
    BuildChunk(image_set, v, sampling[v], downsampled_mattes[v], reachable[v], y, block,
               column_of_voxel, max_pixel_opacity, foreground_alpha, min_row_weight, &chunks[i]);
  });
  RaySystem system;
  system.matrix.num_cols = num_columns;
  // Reserved up front: growing the arrays chunk by chunk copied them over
  // and over (seconds on a 200-voxel grid, without a chance to cancel).
  size_t num_rows = 0, num_entries = 0;
  for (const RowChunk& chunk : chunks) {
    num_rows += chunk.lengths.size();
    num_entries += chunk.cols.size();
  }
  system.matrix.row_offsets.reserve(system.matrix.row_offsets.size() + num_rows);
  system.matrix.cols.reserve(num_entries);
  system.matrix.values.reserve(num_entries);
  system.rhs.reserve(num_rows);
  for (RowChunk& chunk : chunks) {
    progress.CheckCancelled();
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
