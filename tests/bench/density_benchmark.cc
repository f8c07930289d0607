// Benchmark of the density stage (thesis 3.3): 8 pinhole views at 1024^2 into
// a 128^3 grid, beside a straightforward reference implementation of the same
// model run in the same process.
//
// The reference computes exactly what ReconstructDensity computes, without
// its accelerations: one ray per full-resolution pixel (no downsampling),
// footprint means by looping over the pixels (no summed-area tables), serial
// assembly of the system; it shares the exact voxel traversal and the solver.
// It is too slow at 128^3 / 1024^2, so it runs at n^3 / (8n)^2 for n = 16,
// 32, 64 (the same pixels-per-voxel ratio) and its time is extrapolated to
// n = 128 with the scaling measured between 32 and 64. The fast
// implementation runs at every size too, so ratios at equal sizes are
// measured, not extrapolated.
//
// Memory: peak bytes allocated through operator new during the call (the
// stage's vectors, the system, the grid), counted by the hooks below.
//
// Agreement: at each equal size the fast grid is compared with the
// reference's solution on the same voxel block (occupied-voxel IoU, mean
// opacity difference); the program fails beyond the tolerances (see
// kSameRays, kDefaults).
//
// usage: sylva_density_benchmark [--quick]   (--quick: n = 64 at most; smoke test)
#include <malloc.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/voxel_traversal.h"
#include "core/util/memory.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "reconstruct/density/sparse_system.h"
#include "reconstruct/density/view_sampling.h"
#include "tests/bench/agreement.h"

// ---- Heap accounting -------------------------------------------------------
namespace {
std::atomic<int64_t> g_heap_current{0};
std::atomic<int64_t> g_heap_peak{0};

void CountAllocation(void* pointer) {
  const int64_t now = g_heap_current.fetch_add(static_cast<int64_t>(malloc_usable_size(pointer))) +
                      static_cast<int64_t>(malloc_usable_size(pointer));
  int64_t peak = g_heap_peak.load();
  while (now > peak && !g_heap_peak.compare_exchange_weak(peak, now)) {
  }
}
void* Allocate(size_t size) {
  void* pointer = std::malloc(size == 0 ? 1 : size);
  if (pointer == nullptr) throw std::bad_alloc();
  CountAllocation(pointer);
  return pointer;
}
void Release(void* pointer) {
  if (pointer == nullptr) return;
  g_heap_current.fetch_sub(static_cast<int64_t>(malloc_usable_size(pointer)));
  std::free(pointer);
}
void* AllocateAligned(size_t size, std::align_val_t alignment) {
  void* pointer = nullptr;
  const size_t align = std::max(static_cast<size_t>(alignment), sizeof(void*));
  if (posix_memalign(&pointer, align, size == 0 ? 1 : size) != 0) throw std::bad_alloc();
  CountAllocation(pointer);
  return pointer;
}
}  // namespace

void* operator new(size_t size) { return Allocate(size); }
void* operator new[](size_t size) { return Allocate(size); }
void* operator new(size_t size, std::align_val_t a) { return AllocateAligned(size, a); }
void* operator new[](size_t size, std::align_val_t a) { return AllocateAligned(size, a); }
void operator delete(void* p) noexcept { Release(p); }
void operator delete[](void* p) noexcept { Release(p); }
void operator delete(void* p, size_t) noexcept { Release(p); }
void operator delete[](void* p, size_t) noexcept { Release(p); }
void operator delete(void* p, std::align_val_t) noexcept { Release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { Release(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { Release(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { Release(p); }

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The benchmark scene at full size: 8 pinhole views of a synthetic tree.
struct Scene {
  ImageSet image_set;
  std::vector<FloatImage> mattes;
};

Scene MakeScene(int image_size) {
  SyntheticDatasetOptions options;
  options.seed = 1;
  options.num_views = 8;
  options.num_held_out = 0;
  options.image_size = image_size;
  options.samples_per_axis = 2;
  SyntheticDataset data = MakeSyntheticDataset(options);
  return {data.image_set, std::move(data.mattes)};
}

// The same scene at a smaller image size: intrinsics scaled, mattes box-filtered.
Scene Shrink(const Scene& scene, int factor) {
  Scene small{scene.image_set, {}};
  for (auto& [id, camera] : small.image_set.cameras) {
    std::vector<double> params = camera.params();
    for (double& p : params) p /= factor;  // f and c scale; PINHOLE has no distortion
    camera = Camera(camera.model(), camera.width() / factor, camera.height() / factor, params);
  }
  for (const FloatImage& matte : scene.mattes) small.mattes.push_back(DownsampleBox(matte, factor));
  return small;
}

// ---- The straightforward reference -----------------------------------------

double PixelLoopMean(const FloatImage& matte, double x0, double y0, double x1, double y1) {
  const int i0 = std::max(0, static_cast<int>(std::ceil(x0 - 0.5)));
  const int j0 = std::max(0, static_cast<int>(std::ceil(y0 - 0.5)));
  const int i1 = std::min(matte.width(), std::max(i0 + 1, static_cast<int>(std::ceil(x1 - 0.5))));
  const int j1 = std::min(matte.height(), std::max(j0 + 1, static_cast<int>(std::ceil(y1 - 0.5))));
  if (i0 >= matte.width() || j0 >= matte.height() || i1 <= 0 || j1 <= 0) return -1.0;
  double sum = 0.0;
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) sum += matte.at(i, j);
  return sum / ((i1 - i0) * (j1 - j0));
}

float ReferenceInitialValue(const Scene& scene, const VoxelBlock& block,
                            const Eigen::Vector3i& ijk) {
  float best = std::numeric_limits<float>::infinity();
  for (int v = 0; v < scene.image_set.NumViews(); ++v) {
    Eigen::AlignedBox2d rect;
    bool visible = true;
    for (int corner = 0; corner < 8 && visible; ++corner) {
      const Eigen::Vector3d p =
          block.lower_corner +
          block.voxel_size *
              (ijk + Eigen::Vector3i(corner & 1, (corner >> 1) & 1, corner >> 2)).cast<double>();
      Eigen::Vector2d pixel;
      visible = scene.image_set.Project(v, p, &pixel);
      rect.extend(pixel);
    }
    if (!visible) continue;
    const double mean = PixelLoopMean(scene.mattes[v], rect.min().x(), rect.min().y(),
                                      rect.max().x(), rect.max().y());
    if (mean >= 0) best = std::min(best, static_cast<float>(mean));
  }
  return std::isinf(best) ? 0.0f : best;
}

// The reference's solution: opacity per voxel of the block (linear index; 0
// where carved) and the seconds it took.
struct ReferenceResult {
  double seconds = 0;
  std::vector<float> opacity;
};

ReferenceResult ReferenceDensity(const Scene& scene, const VoxelBlock& block,
                                 const DensityOptions& options) {
  const Clock::time_point start = Clock::now();
  std::vector<int32_t> column_of_voxel(block.NumVoxels(), -1);
  std::vector<double> x;
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    const float alpha = ReferenceInitialValue(scene, block, block.VoxelFromLinear(i));
    if (alpha <= 0 || alpha < options.carve_threshold) continue;
    column_of_voxel[i] = static_cast<int32_t>(x.size());
    x.push_back(-std::log(1.0 - std::min<double>(alpha, options.max_pixel_opacity)));
  }
  SparseRows a;
  a.num_cols = static_cast<int64_t>(x.size());
  std::vector<double> b;
  for (int v = 0; v < scene.image_set.NumViews(); ++v) {
    const FloatImage& matte = scene.mattes[v];
    for (int j = 0; j < matte.height(); ++j) {
      for (int i = 0; i < matte.width(); ++i) {
        const double alpha = matte.at(i, j);
        const double weight = std::max(1.0 - alpha, options.min_row_weight);
        const Ray3d ray = scene.image_set.RayThroughPixel(v, Eigen::Vector2d(i + 0.5, j + 0.5));
        const size_t before = a.cols.size();
        TraverseVoxels(block, ray, [&](int64_t voxel, double length) {
          if (column_of_voxel[voxel] < 0) return;
          a.cols.push_back(column_of_voxel[voxel]);
          a.values.push_back(static_cast<float>(length / block.voxel_size * weight));
        });
        if (a.cols.size() == before) continue;
        a.row_offsets.push_back(static_cast<int64_t>(a.cols.size()));
        b.push_back(-std::log(1.0 - std::min(alpha, options.max_pixel_opacity)) * weight);
      }
    }
  }
  const CglsOptions solve{options.max_iterations, options.tolerance};
  const SparseRows transposed = a.Transposed();
  SolveProjectedGradient(a, &transposed, b, solve, &x, nullptr);
  ReferenceResult result;
  result.opacity.assign(block.NumVoxels(), 0.0f);
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    if (column_of_voxel[i] >= 0) result.opacity[i] = 1.0f - std::exp(-x[column_of_voxel[i]]);
  }
  result.seconds = Seconds(start);
  return result;
}

// ---- Agreement -----------------------------------------------------------------

// A voxel is occupied from this opacity on (the fast grid drops opacities
// under DensityOptions::min_output_opacity, 1e-3; faint voxels are noise).
constexpr float kOccupiedOpacity = 0.05f;

struct GridAgreement {
  double iou = 0;                      // of the occupied voxels
  double mean_opacity_difference = 0;  // mean |fast - reference| over the union
};

GridAgreement CompareOnBlock(const DensityGrid& fast, const VoxelBlock& block,
                             const std::vector<float>& reference) {
  int64_t both = 0, either = 0;
  double difference = 0;
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    const float ours = fast.Value(block.VoxelFromLinear(i)), theirs = reference[i];
    const bool occupied = ours >= kOccupiedOpacity, reference_occupied = theirs >= kOccupiedOpacity;
    if (!occupied && !reference_occupied) continue;
    ++either;
    both += occupied && reference_occupied;
    difference += std::abs(ours - theirs);
  }
  if (either == 0) return {1.0, 0.0};
  return {static_cast<double>(both) / either, difference / either};
}

// ---- Measurements ------------------------------------------------------------

struct Measurement {
  double seconds = 0;
  // Each step's best time over the repetitions (steps vary apart on a noisy
  // machine): bounds, init, system, solve.
  std::array<double, 4> best_steps = {1e300, 1e300, 1e300, 1e300};
  int64_t peak_heap_bytes = 0;
  DensitySummary summary;
  std::optional<DensityGrid> grid;  // of the fastest run
};

Measurement MeasureFast(const Scene& scene, const DensityOptions& options, int repetitions) {
  Measurement best;
  best.seconds = 1e300;
  for (int r = 0; r < repetitions; ++r) {
    const int64_t baseline = g_heap_current.load();
    g_heap_peak.store(baseline);
    DensitySummary summary;
    const Clock::time_point start = Clock::now();
    const DensityGrid grid =
        ReconstructDensity(scene.image_set, scene.mattes, options, nullptr, &summary);
    const double seconds = Seconds(start);
    best.peak_heap_bytes = std::max(best.peak_heap_bytes, g_heap_peak.load() - baseline);
    const std::array<double, 4> steps = {summary.seconds_bounds, summary.seconds_init,
                                         summary.seconds_system, summary.seconds_solve};
    for (int k = 0; k < 4; ++k) best.best_steps[k] = std::min(best.best_steps[k], steps[k]);
    if (seconds < best.seconds) {
      best.seconds = seconds;
      best.summary = summary;
      best.grid = grid;
    }
  }
  return best;
}

VoxelBlock BlockOf(const DensitySummary& summary) {
  VoxelBlock block;
  block.lower_corner = summary.bounds.min();
  block.voxel_size = summary.voxel_size;
  block.dims = summary.grid_dims;
  return block;
}

// Two comparisons with the reference on its voxel block:
//  - same rays: the fast code with DensityOptions::pixels_per_voxel at its
//    maximum, 64, so that it downsamples nothing here (a voxel covers ~4-8
//    pixels across at (8n)^2) and traces every pixel as the reference does.
//    What remains is mainly the fast code's rescaled initial solution
//    (InitialSolution), so the solutions nearly match: measured IoU 0.967,
//    0.958, 0.926 and mean |opacity difference| 0.006, 0.007, 0.010 at
//    n = 16, 32, 64 (full mode within 0.004 of these).
//  - defaults (the timed run): one ray per downsampled pixel, about one per
//    voxel footprint, 1/36 of the rays at 64^3. The least squares, 50
//    iterations from the same start, ends elsewhere on thin branches, so the
//    occupied voxels differ much more: measured IoU 0.740, 0.638, 0.468 and
//    mean |opacity difference| 0.076, 0.080, 0.079 (full mode within
//    0.008). This bounds what the downsampling costs, not the
//    implementation; a one-voxel shift of the fast grid fails "same rays"
//    at every size but "defaults" only at 16^3.
// Tolerances: the measured figures with a margin.
struct GridTolerance {
  double min_iou;
  double max_mean_opacity_difference;
};
constexpr GridTolerance kSameRays{0.85, 0.03};
constexpr GridTolerance kDefaults{0.35, 0.12};

void CheckAgreement(const std::string& what, int n, const GridAgreement& grids,
                    const GridTolerance& tolerance, Agreement* agreement) {
  std::printf("%34s %s: occupied-voxel IoU %.3f, mean |opacity difference| %.3f\n", "",
              what.c_str(), grids.iou, grids.mean_opacity_difference);
  const std::string at = ", " + what + ", " + std::to_string(n) + "^3";
  agreement->AtLeast("occupied-voxel IoU (opacity >= 0.05)" + at, grids.iou, tolerance.min_iou);
  agreement->AtMost("mean |opacity difference| over occupied voxels" + at,
                    grids.mean_opacity_difference, tolerance.max_mean_opacity_difference);
}

void PrintRow(const char* what, int n, int size, double seconds, double reference) {
  std::printf("%-34s %4d^3 %5d^2  %9.3f s", what, n, size, seconds);
  if (reference > 0)
    std::printf("   reference %9.3f s   ratio %7.1fx", reference, reference / seconds);
  std::printf("\n");
}

// Timed runs of the fast code at full size.
constexpr int kFastRepetitions = 5;

int Main(bool quick) {
  const int full_size = quick ? 512 : 1024;
  const int full_n = quick ? 64 : 128;
  std::printf("Density benchmark: 8 pinhole views, synthetic tree (seed 1); %s\n",
              quick ? "quick mode" : "full mode");
  const Clock::time_point render_start = Clock::now();
  const Scene scene = MakeScene(full_size);
  std::printf("(rendered the views in %.2f s)\n\n", Seconds(render_start));

  // The reference has neither the test of the views against each other nor
  // the choice of resolution from thin structure: both are off for the
  // comparison, and measured once on their own below.
  DensityOptions options;
  options.resolution = full_n;
  options.max_resolution = 0;
  options.view_outlier_fraction = 0.0;
  const Measurement fast = MeasureFast(scene, options, kFastRepetitions);
  std::printf(
      "Fast, %d threads, %d^3 from %d^2: best of %d %.3f s (goal at 128^3 from 1024^2: "
      "< 0.5 s, issue 18), peak heap %.1f MB\n",
      static_cast<int>(
          tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)),
      full_n, full_size, kFastRepetitions, fast.seconds, fast.peak_heap_bytes / 1e6);
  std::printf("  %s\n", fast.summary.BriefReport().c_str());
  std::printf("  Each step's best of %d: bounds %.3f, init %.3f, system %.3f, solve %.3f s\n\n",
              kFastRepetitions, fast.best_steps[0], fast.best_steps[1], fast.best_steps[2],
              fast.best_steps[3]);
  {
    // The solver with Cauchy steps (not the default: README), at the
    // iteration count that reaches the default's silhouette fit on the
    // synthetic trees (sylva_density_iterations_probe).
    DensityOptions cauchy = options;
    cauchy.cauchy_every = 3;
    cauchy.max_iterations = 20;
    const Measurement with_cauchy = MeasureFast(scene, cauchy, kFastRepetitions);
    std::printf(
        "Fast with Cauchy steps (Density.cauchy_every=3, max_iterations=20): best of %d %.3f s "
        "(%.2fx the default's), solve %.3f s; |r| %.4g (default %.4g)\n\n",
        kFastRepetitions, with_cauchy.seconds, with_cauchy.seconds / fast.seconds,
        with_cauchy.best_steps[3], with_cauchy.summary.solves.back().final_residual_norm,
        fast.summary.solves.back().final_residual_norm);
  }
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    const Measurement serial = MeasureFast(scene, options, 1);
    std::printf("Fast, 1 thread: %.3f s\n\n", serial.seconds);
  }

  {
    DensityOptions defaults;
    defaults.resolution = full_n;
    defaults.max_resolution = full_n;  // the same grid; the thin-structure share is still measured
    const Measurement checked = MeasureFast(scene, defaults, 1);
    std::printf(
        "Fast with the view-consensus test and the thin-structure probe (defaults at "
        "%d^3): %.3f s, of which bounds and both checks %.3f s (%.3f s without them)\n\n",
        full_n, checked.seconds, checked.summary.seconds_bounds, fast.summary.seconds_bounds);
  }

  // Equal sizes: n^3 from (8n)^2 images, reference beside the fast version.
  std::vector<int> sizes = {16, 32, 64};
  std::vector<double> reference_seconds;
  Agreement agreement;
  for (int n : sizes) {
    const int factor = full_size / (8 * n);
    if (factor < 1) break;
    const Scene small = factor > 1 ? Shrink(scene, factor) : scene;
    DensityOptions small_options = options;
    small_options.resolution = n;
    const Measurement m = MeasureFast(small, small_options, 3);
    const VoxelBlock block = BlockOf(m.summary);
    const ReferenceResult reference = ReferenceDensity(small, block, small_options);
    reference_seconds.push_back(reference.seconds);
    PrintRow("fast vs reference (measured)", n, full_size / factor, m.seconds, reference.seconds);
    CheckAgreement("defaults", n, CompareOnBlock(*m.grid, block, reference.opacity), kDefaults,
                   &agreement);
    DensityOptions every_pixel = small_options;
    every_pixel.pixels_per_voxel = 64.0;
    const Measurement same_rays = MeasureFast(small, every_pixel, 1);
    CheckAgreement("same rays", n, CompareOnBlock(*same_rays.grid, block, reference.opacity),
                   kSameRays, &agreement);
  }
  const size_t k = reference_seconds.size();
  if (k >= 2) {
    const double growth = reference_seconds[k - 1] / reference_seconds[k - 2];
    double extrapolated = reference_seconds[k - 1];
    for (int n = sizes[k - 1]; n < full_n; n *= 2) extrapolated *= growth;
    std::printf("\nReference time grows %.1fx per doubling of n (exponent %.2f);\n", growth,
                std::log2(growth));
    PrintRow("fast vs reference (extrapolated)", full_n, full_size, fast.seconds, extrapolated);
  }
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  std::printf("\nProcess peak RSS %.1f MB (includes the rendered photos).\n",
              usage.ru_maxrss / 1e3);
  return agreement.ExitCode();
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  // As the sylva binary and the app do: the app runs the density again after
  // every edit, in one process, as this benchmark's repeated runs do.
  sylva::KeepFreedMemoryForReuse();
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::Main(quick);
}
