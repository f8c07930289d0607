#include "reconstruct/density/view_sampling.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/util/check.h"

namespace sylva {
namespace {

// Z slices per parallel task in MinFootprintMeans; each task projects its
// slices' corner layers once per view, so larger chunks project fewer
// points twice.
constexpr int kSlicesPerTask = 4;

}  // namespace

Eigen::Vector2d ViewSampling::RayPosition(int pixel_x, int pixel_y, int a, int b) const {
  const int x0 = pixel_x * factor, y0 = pixel_y * factor;
  const int block_width = std::min(x0 + factor, original_width) - x0;
  const int block_height = std::min(y0 + factor, original_height) - y0;
  return Eigen::Vector2d(x0 + block_width * (a + 0.5) / rays_per_axis,
                         y0 + block_height * (b + 0.5) / rays_per_axis);
}

ViewSampling MakeViewSampling(const ImageSet& image_set, int view_idx,
                              const Eigen::Vector3d& center_in_world, double voxel_size,
                              double pixels_per_voxel, int rays_per_axis) {
  const View& view = image_set.views.at(view_idx);
  const Camera& camera = image_set.CameraOf(view);
  const Eigen::Vector3d center_in_cam = view.cam_from_world * center_in_world;
  double voxel_pixels = 0.5 * (camera.FocalLengthX() + camera.FocalLengthY()) * voxel_size;
  if (!camera.IsOrthographic()) voxel_pixels /= std::max(center_in_cam.z(), 1e-12 * voxel_size);
  ViewSampling sampling;
  sampling.factor = std::max(1, static_cast<int>(std::floor(voxel_pixels / pixels_per_voxel)));
  sampling.factor = std::min(sampling.factor, std::max(camera.width(), camera.height()));
  sampling.rays_per_axis = rays_per_axis;
  sampling.original_width = camera.width();
  sampling.original_height = camera.height();
  return sampling;
}

ViewProjector::ViewProjector(const ImageSet& image_set, int view_idx)
    : camera_(&image_set.CameraOf(view_idx)),
      rotation_(image_set.views.at(view_idx).cam_from_world.rotation.toRotationMatrix()),
      translation_(image_set.views.at(view_idx).cam_from_world.translation),
      orthographic_(camera_->IsOrthographic()),
      plain_pinhole_(!camera_->IsOrthographic() && !camera_->HasDistortion()),
      focal_(camera_->FocalLengthX(), camera_->FocalLengthY()),
      principal_point_(camera_->PrincipalPoint()) {}

namespace {

// Projections of one z layer of voxel corners: (nx + 1) x (ny + 1) points.
struct CornerLayer {
  std::vector<Eigen::Vector2f> pixels;
  std::vector<char> valid;
};

// Rows [row_begin, row_end) of the layer are projected; the others are left
// as they were.
void ProjectCornerLayer(const ViewProjector& projector, const VoxelBlock& block, int z,
                        int row_begin, int row_end, CornerLayer* layer) {
  const int nx = block.dims.x() + 1, ny = block.dims.y() + 1;
  layer->pixels.resize(static_cast<size_t>(nx) * ny);
  layer->valid.resize(layer->pixels.size());
  for (int y = row_begin; y < row_end; ++y) {
    for (int x = 0; x < nx; ++x) {
      const Eigen::Vector3d corner =
          block.lower_corner + block.voxel_size * Eigen::Vector3d(x, y, z);
      Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
      const size_t i = static_cast<size_t>(y) * nx + x;
      layer->valid[i] = projector.Project(corner, &pixel);
      layer->pixels[i] = pixel.cast<float>();
    }
  }
}

// Footprint mean of voxel (x, y) between two corner layers; -1 if unseen.
double FootprintMean(const CornerLayer& lower, const CornerLayer& upper, int nx, int x, int y,
                     const SummedAreaTable& table) {
  float x0 = std::numeric_limits<float>::max(), y0 = x0;
  float x1 = std::numeric_limits<float>::lowest(), y1 = x1;
  for (const CornerLayer* layer : {&lower, &upper}) {
    for (int dy = 0; dy < 2; ++dy) {
      for (int dx = 0; dx < 2; ++dx) {
        const size_t i = static_cast<size_t>(y + dy) * nx + x + dx;
        if (!layer->valid[i]) return -1.0;
        const Eigen::Vector2f& p = layer->pixels[i];
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
      }
    }
  }
  return table.BoxMean(x0, y0, x1, y1);
}

}  // namespace

std::vector<SummedAreaTable> MakeSummedAreaTables(const std::vector<FloatImage>& images) {
  std::vector<std::unique_ptr<SummedAreaTable>> built(images.size());
  tbb::parallel_for(size_t{0}, images.size(),
                    [&](size_t i) { built[i] = std::make_unique<SummedAreaTable>(images[i]); });
  std::vector<SummedAreaTable> tables;
  tables.reserve(images.size());
  for (auto& table : built) tables.push_back(std::move(*table));
  return tables;
}

namespace {

// Bricks of kBlockSide x kBlockSide voxels across (through a task's z
// slices) whose footprints in a view cover only zero pixels: the bounding
// rectangle of the brick's projected corners (a superset of each voxel's
// footprint), widened to the pixels BoxMean could sample (it samples at
// least one pixel), lies inside the image and holds no non-zero pixel. Each
// voxel of such a brick has a footprint mean of exactly 0 there, found
// without a look-up per voxel.
constexpr int kBlockSide = 4;

// The test above on a rectangle [x0, x1] x [y0, y1] (pixel coordinates).
bool ZeroRect(float x0, float y0, float x1, float y1, const SummedAreaTable& table) {
  // BoxMean samples pixels [ceil(x0 - 0.5), max(ceil(x1 - 0.5), that + 1)):
  // within [i0, i1 + 1) below. i0 >= 1 keeps every voxel's box from
  // reading as outside the image (BoxMean's -1) at the left and top.
  // (In double, as BoxMean rounds; clamped before the conversion, as a
  // corner just in front of a pinhole projects arbitrarily far out.)
  const auto pixel_of = [](float coordinate) {
    return static_cast<int>(std::clamp(std::ceil(double{coordinate} - 0.5), -1e9, 1e9));
  };
  const int i0 = pixel_of(x0), i1 = pixel_of(x1), j0 = pixel_of(y0), j1 = pixel_of(y1);
  if (i0 < 1 || j0 < 1 || i1 + 1 > table.width() || j1 + 1 > table.height()) return false;
  return table.AllZero(i0, j0, i1 + 1, j1 + 1);
}

// The same test from the 8 corners of each brick alone: 1/16 of the
// projections per layer, and 2 layers instead of the slices' 5. A pinhole's
// (or an orthographic camera's) image of a box lies in its corners'
// rectangle; lens distortion bends the box's edges, so that its image may
// bulge past that rectangle: the rectangle is widened by twice the largest
// gap, over the brick's 12 edges, between an edge's projected midpoint and
// the middle of its projected ends (over a brick the distortion is nearly
// quadratic, which bends an edge by at most that gap; its image's extremes
// lie on the images of the box's edges). A voxel corner inside the brick may
// round to a float a step outside, so the rectangle is also widened by a
// few float steps (never claims a brick that a test of every voxel corner
// would not, up to that rounding).
// Float steps (relative) the corners' rectangle is widened by, for the
// rounding of the voxel corners inside it.
constexpr float kCornerRoundingSteps = 4.0f;
// How many times its edges' midpoint gap a distorted brick's rectangle is
// widened by, and the largest gap (pixels) trusted so: where the distortion
// bends a brick's edges more, it is not quadratic over them, and the
// brick is left to the voxels' own footprints.
constexpr float kEdgeBendFactor = 2.0f;
constexpr float kMaxTrustedBend = 2.0f;

// Projections of points of the brick lattice of one task: for each z of
// `zs` (in voxels), (bx + 1) x (by + 1) points at brick corners, moved to
// the middle of the brick's edge along x and/or y where asked (offset 0.5).
struct BrickLattice {
  int bx = 0, by = 0;
  std::vector<Eigen::Vector2f> pixels;
  std::vector<char> valid;

  size_t Index(int layer, int cx, int cy) const {
    return (static_cast<size_t>(layer) * (by + 1) + cy) * (bx + 1) + cx;
  }
};

BrickLattice ProjectBrickLattice(const ViewProjector& projector, const VoxelBlock& block,
                                 const std::vector<double>& zs, double x_offset, double y_offset) {
  const int nx = block.dims.x(), ny = block.dims.y();
  BrickLattice lattice;
  lattice.bx = (nx + kBlockSide - 1) / kBlockSide;
  lattice.by = (ny + kBlockSide - 1) / kBlockSide;
  lattice.pixels.resize(zs.size() * (lattice.bx + 1) * (lattice.by + 1));
  lattice.valid.resize(lattice.pixels.size());
  // A brick's corner (clamped to the block), or the middle of its edge.
  const auto coordinate = [](int c, int n, double offset) {
    const double lo = std::min(n, c * kBlockSide);
    if (offset == 0.0) return lo;
    return 0.5 * (lo + std::min(n, (c + 1) * kBlockSide));
  };
  for (size_t l = 0; l < zs.size(); ++l) {
    for (int cy = 0; cy <= lattice.by; ++cy) {
      for (int cx = 0; cx <= lattice.bx; ++cx) {
        const Eigen::Vector3d corner =
            block.lower_corner + block.voxel_size * Eigen::Vector3d(coordinate(cx, nx, x_offset),
                                                                    coordinate(cy, ny, y_offset),
                                                                    zs[l]);
        Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
        const size_t i = lattice.Index(static_cast<int>(l), cx, cy);
        lattice.valid[i] = projector.Project(corner, &pixel);
        lattice.pixels[i] = pixel.cast<float>();
      }
    }
  }
  return lattice;
}

void MarkZeroBricksFromCorners(const ViewProjector& projector, const VoxelBlock& block, int z_begin,
                               int z_end, const SummedAreaTable& table, std::vector<char>* zero) {
  const std::vector<double> ends = {static_cast<double>(z_begin), static_cast<double>(z_end)};
  const BrickLattice corners = ProjectBrickLattice(projector, block, ends, 0.0, 0.0);
  const int bx = corners.bx, by = corners.by;
  // With distortion: the midpoints of the edges along x and y (at both
  // ends) and along z (halfway).
  const bool bends = !projector.KeepsBoxesInCornerRects();
  BrickLattice x_mids, y_mids, z_mids;
  if (bends) {
    x_mids = ProjectBrickLattice(projector, block, ends, 0.5, 0.0);
    y_mids = ProjectBrickLattice(projector, block, ends, 0.0, 0.5);
    z_mids = ProjectBrickLattice(projector, block, {0.5 * (z_begin + z_end)}, 0.0, 0.0);
  }
  zero->assign(static_cast<size_t>(bx) * by, 0);
  for (int cy = 0; cy < by; ++cy) {
    for (int cx = 0; cx < bx; ++cx) {
      float x0 = std::numeric_limits<float>::max(), y0 = x0;
      float x1 = std::numeric_limits<float>::lowest(), y1 = x1;
      bool all_valid = true;
      for (int corner = 0; corner < 8; ++corner) {
        const size_t i = corners.Index(corner >> 2, cx + (corner & 1), cy + ((corner >> 1) & 1));
        all_valid = all_valid && corners.valid[i];
        x0 = std::min(x0, corners.pixels[i].x());
        x1 = std::max(x1, corners.pixels[i].x());
        y0 = std::min(y0, corners.pixels[i].y());
        y1 = std::max(y1, corners.pixels[i].y());
      }
      float bend = 0.0f;
      if (bends && all_valid) {
        // Each edge: its midpoint's projection and its two ends'.
        const auto gap = [&](const BrickLattice& mids, size_t mid, size_t a, size_t b) {
          all_valid = all_valid && mids.valid[mid];
          const Eigen::Vector2f chord = 0.5f * (corners.pixels[a] + corners.pixels[b]);
          bend = std::max(bend, (mids.pixels[mid] - chord).cwiseAbs().maxCoeff());
        };
        for (int l = 0; l < 2; ++l) {
          for (int d = 0; d < 2; ++d) {
            gap(x_mids, x_mids.Index(l, cx, cy + d), corners.Index(l, cx, cy + d),
                corners.Index(l, cx + 1, cy + d));
            gap(y_mids, y_mids.Index(l, cx + d, cy), corners.Index(l, cx + d, cy),
                corners.Index(l, cx + d, cy + 1));
          }
        }
        for (int d = 0; d < 4; ++d) {
          const int x = cx + (d & 1), y = cy + (d >> 1);
          gap(z_mids, z_mids.Index(0, x, y), corners.Index(0, x, y), corners.Index(1, x, y));
        }
      }
      if (!all_valid || bend > kMaxTrustedBend) continue;
      const auto widen = [bend](float value, float direction) {
        return value + direction * (kEdgeBendFactor * bend +
                                    kCornerRoundingSteps * std::numeric_limits<float>::epsilon() *
                                        std::max(1.0f, std::abs(value)));
      };
      (*zero)[static_cast<size_t>(cy) * bx + cx] =
          ZeroRect(widen(x0, -1), widen(y0, -1), widen(x1, 1), widen(y1, 1), table);
    }
  }
}

// Calls visit(view, linear voxel index, footprint mean) for every voxel of
// `block` and every view of `views` that sees it (the voxel in front of the
// camera and its footprint at least partly inside the image), except where
// a voxel's result is already settled: a visitor whose result is final once
// `visit.settling_zeros` views gave a mean of 0 (the minimum: 1) hears of
// no other view of the bricks that so many views see empty. All calls for
// one voxel come from one thread, in the order of `views`, so `visit` may
// update per-voxel state without locks; calls for different voxels run in
// parallel.
template <typename Visit>
void ForEachFootprint(const ImageSet& image_set, const std::vector<SummedAreaTable>& tables,
                      const std::vector<int>& views, const VoxelBlock& block,
                      const ProgressTask& progress, Visit&& visit) {
  SYLVA_CHECK(static_cast<int>(tables.size()) == image_set.NumViews());
  std::vector<ViewProjector> projectors;
  for (int v = 0; v < image_set.NumViews(); ++v) projectors.emplace_back(image_set, v);
  const int nx = block.dims.x(), ny = block.dims.y(), nz = block.dims.z();
  const int num_tasks = (nz + kSlicesPerTask - 1) / kSlicesPerTask;
  const int bx = (nx + kBlockSide - 1) / kBlockSide, by = (ny + kBlockSide - 1) / kBlockSide;
  const size_t num_bricks = static_cast<size_t>(bx) * by;
  tbb::parallel_for(0, num_tasks, [&](int task) {
    progress.CheckCancelled();
    const int z_begin = task * kSlicesPerTask, z_end = std::min(nz, z_begin + kSlicesPerTask);
    // The bricks' zero views, from their corners.
    std::vector<std::vector<char>> zero(views.size());
    std::vector<int> zero_views(num_bricks, 0);
    for (size_t k = 0; k < views.size(); ++k) {
      MarkZeroBricksFromCorners(projectors[views[k]], block, z_begin, z_end, tables[views[k]],
                                &zero[k]);
      for (size_t b = 0; b < num_bricks; ++b) zero_views[b] += zero[k][b];
    }
    // Whether brick b is known to be empty in views[k].
    const auto zero_in = [&](size_t k, size_t b) { return zero[k][b] != 0; };
    // For each voxel of brick b in the slices, calls f(x, y, z, linear index).
    const auto for_voxels = [&](size_t brick, auto&& f) {
      const int cx = static_cast<int>(brick % bx), cy = static_cast<int>(brick / bx);
      for (int z = z_begin; z < z_end; ++z) {
        for (int y = cy * kBlockSide; y < std::min(ny, (cy + 1) * kBlockSide); ++y) {
          for (int x = cx * kBlockSide; x < std::min(nx, (cx + 1) * kBlockSide); ++x) {
            f(x, y, z, block.LinearIndex({x, y, z}));
          }
        }
      }
    };
    // Settled bricks hear only of their zero views.
    std::vector<char> live(num_bricks, 1);
    for (size_t b = 0; b < num_bricks; ++b) {
      if (zero_views[b] < visit.settling_zeros) continue;
      live[b] = 0;
      for_voxels(b, [&](int, int, int, int64_t i) {
        for (size_t k = 0; k < views.size() && visit.Wants(i); ++k) {
          if (zero_in(k, b)) visit(views[k], i, 0.0);
        }
      });
    }
    std::vector<CornerLayer> layers(z_end - z_begin + 1);
    for (size_t k = 0; k < views.size(); ++k) {
      const int v = views[k];
      // The corner rows the live bricks that are not zero in v need.
      int row_begin = ny + 1, row_end = 0;
      for (size_t b = 0; b < num_bricks; ++b) {
        if (!live[b] || zero_in(k, b)) continue;
        const int cy = static_cast<int>(b / bx);
        row_begin = std::min(row_begin, cy * kBlockSide);
        row_end = std::max(row_end, std::min(ny, (cy + 1) * kBlockSide) + 1);
      }
      if (row_begin < row_end) {
        for (int l = 0; l <= z_end - z_begin; ++l) {
          ProjectCornerLayer(projectors[v], block, z_begin + l, row_begin, row_end, &layers[l]);
        }
      }
      for (size_t b = 0; b < num_bricks; ++b) {
        if (!live[b]) continue;
        const bool brick_zero = zero_in(k, b);
        for_voxels(b, [&](int x, int y, int z, int64_t i) {
          if (!visit.Wants(i)) return;
          const int l = z - z_begin;
          const double mean =
              brick_zero ? 0.0 : FootprintMean(layers[l], layers[l + 1], nx + 1, x, y, tables[v]);
          if (mean >= 0.0) visit(v, i, mean);
        });
      }
    }
  });
}

std::vector<int> AllViews(const ImageSet& image_set) {
  std::vector<int> views(image_set.NumViews());
  for (int v = 0; v < image_set.NumViews(); ++v) views[v] = v;
  return views;
}

// Keeps the smallest footprint mean per voxel.
struct MinimumVisitor {
  std::vector<float>* result;
  int settling_zeros = 1;
  bool Wants(int64_t i) const { return (*result)[i] != 0.0f; }  // 0 cannot get lower
  void operator()(int, int64_t i, double mean) const {
    (*result)[i] = std::min((*result)[i], static_cast<float>(mean));
  }
};

// Keeps the `rank` + 1 smallest footprint means per voxel, sorted.
struct LowestVisitor {
  int kept;                    // rank + 1
  std::vector<float>* lowest;  // kept values per voxel, +inf where unfilled
  int settling_zeros = kept;
  bool Wants(int64_t i) const { return (*lowest)[i * kept + kept - 1] != 0.0f; }
  void operator()(int, int64_t i, double mean) const {
    float* values = lowest->data() + i * kept;
    float value = static_cast<float>(mean);
    for (int k = 0; k < kept; ++k) {
      if (value < values[k]) std::swap(value, values[k]);
    }
  }
};

// Counts the views that see a voxel and those whose footprint mean is at
// most a threshold (the views that carve it away).
struct VetoVisitor {
  const std::vector<char>* wanted;  // null: every voxel
  double threshold;
  FootprintVotes* votes;
  const std::vector<int>* bit_of_view;                   // per image_set view; null: no bits kept
  int settling_zeros = std::numeric_limits<int>::max();  // counts every view
  bool Wants(int64_t i) const { return wanted == nullptr || (*wanted)[i]; }
  void operator()(int v, int64_t i, double mean) const {
    const bool veto = mean <= threshold;
    ++votes->seen[i];
    votes->vetoes[i] += veto;
    if (bit_of_view == nullptr) return;
    const uint64_t bit = uint64_t{1} << (*bit_of_view)[v];
    votes->seen_by[i] |= bit;
    if (veto) votes->vetoed_by[i] |= bit;
  }
};

// Counts per view (indexed by image_set view) in each thread's own arrays:
// integer sums, so the total does not depend on scheduling.
struct PerViewVisitor {
  const std::vector<char>* wanted;
  double threshold;
  tbb::enumerable_thread_specific<ViewVetoCounts>* counts;
  size_t num_views;
  int settling_zeros = std::numeric_limits<int>::max();  // counts every view
  bool Wants(int64_t i) const { return (*wanted)[i]; }
  void operator()(int v, int64_t, double mean) const {
    ViewVetoCounts& local = counts->local();
    if (local.seen.empty()) {
      local.seen.assign(num_views, 0);
      local.vetoes.assign(num_views, 0);
    }
    ++local.seen[v];
    if (mean <= threshold) ++local.vetoes[v];
  }
};

}  // namespace

std::vector<float> MinFootprintMeans(const ImageSet& image_set,
                                     const std::vector<SummedAreaTable>& tables,
                                     const VoxelBlock& block, const ProgressTask& progress,
                                     const std::vector<int>* views) {
  constexpr float kUnseen = std::numeric_limits<float>::infinity();
  std::vector<float> result(block.NumVoxels(), kUnseen);
  ForEachFootprint(image_set, tables, views != nullptr ? *views : AllViews(image_set), block,
                   progress, MinimumVisitor{&result});
  for (float& value : result) {
    if (value == kUnseen) value = 0.0f;
  }
  return result;
}

std::vector<float> LowFootprintMeans(const ImageSet& image_set,
                                     const std::vector<SummedAreaTable>& tables,
                                     const VoxelBlock& block, int rank,
                                     const ProgressTask& progress) {
  if (rank <= 0) return MinFootprintMeans(image_set, tables, block, progress);
  constexpr float kUnseen = std::numeric_limits<float>::infinity();
  const int kept = rank + 1;
  std::vector<float> lowest(block.NumVoxels() * kept, kUnseen);
  ForEachFootprint(image_set, tables, AllViews(image_set), block, progress,
                   LowestVisitor{kept, &lowest});
  std::vector<float> result(block.NumVoxels(), 0.0f);
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    // The rank-th smallest, or the largest seen where fewer views see it.
    for (int k = kept - 1; k >= 0; --k) {
      if (lowest[i * kept + k] != kUnseen) {
        result[i] = lowest[i * kept + k];
        break;
      }
    }
  }
  return result;
}

FootprintVotes CountFootprintVetoes(const ImageSet& image_set,
                                    const std::vector<SummedAreaTable>& tables,
                                    const std::vector<int>& views, const VoxelBlock& block,
                                    double threshold, const std::vector<char>* wanted,
                                    const ProgressTask& progress) {
  FootprintVotes votes;
  votes.seen.assign(block.NumVoxels(), 0);
  votes.vetoes.assign(block.NumVoxels(), 0);
  std::vector<int> bit_of_view;
  if (views.size() <= FootprintVotes::kMaxVoterBits) {
    votes.seen_by.assign(block.NumVoxels(), 0);
    votes.vetoed_by.assign(block.NumVoxels(), 0);
    bit_of_view.assign(image_set.NumViews(), -1);
    for (size_t k = 0; k < views.size(); ++k) bit_of_view[views[k]] = static_cast<int>(k);
  }
  ForEachFootprint(
      image_set, tables, views, block, progress,
      VetoVisitor{wanted, threshold, &votes, bit_of_view.empty() ? nullptr : &bit_of_view});
  return votes;
}

ViewVetoCounts CountVetoesPerView(const FootprintVotes& votes, size_t num_views,
                                  const std::vector<char>& wanted) {
  SYLVA_CHECK(num_views <= FootprintVotes::kMaxVoterBits && votes.seen_by.size() == wanted.size() &&
              votes.vetoed_by.size() == wanted.size());
  ViewVetoCounts counts;
  counts.seen.assign(num_views, 0);
  counts.vetoes.assign(num_views, 0);
  for (size_t i = 0; i < wanted.size(); ++i) {
    if (!wanted[i]) continue;
    for (size_t k = 0; k < num_views; ++k) {
      counts.seen[k] += (votes.seen_by[i] >> k) & 1;
      counts.vetoes[k] += (votes.vetoed_by[i] >> k) & 1;
    }
  }
  return counts;
}

ViewVetoCounts CountVetoesPerView(const ImageSet& image_set,
                                  const std::vector<SummedAreaTable>& tables,
                                  const std::vector<int>& views, const VoxelBlock& block,
                                  double threshold, const std::vector<char>& wanted,
                                  const ProgressTask& progress) {
  SYLVA_CHECK(static_cast<int64_t>(wanted.size()) == block.NumVoxels());
  const size_t num_views = image_set.NumViews();
  tbb::enumerable_thread_specific<ViewVetoCounts> counts;
  ForEachFootprint(image_set, tables, views, block, progress,
                   PerViewVisitor{&wanted, threshold, &counts, num_views});
  ViewVetoCounts total;
  total.seen.assign(views.size(), 0);
  total.vetoes.assign(views.size(), 0);
  for (const ViewVetoCounts& local : counts) {
    if (local.seen.empty()) continue;
    for (size_t k = 0; k < views.size(); ++k) {
      total.seen[k] += local.seen[views[k]];
      total.vetoes[k] += local.vetoes[views[k]];
    }
  }
  return total;
}

}  // namespace sylva
