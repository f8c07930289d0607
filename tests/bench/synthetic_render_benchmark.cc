// Rendering the synthetic tree: MeshRenderer::RenderCoverage (coherent ray
// streams per row, parallel over rows) beside a simple reference that casts
// the same rays one by one through MeshRenderer::CastRay on one thread, so
// the ratio holds on a noisy machine. 256 x 256 pixels, 4 x 4 rays each.
// Before timing, both pictures are compared (mean and largest per-pixel
// coverage difference); the program fails if they disagree.
//
// usage: sylva_synthetic_render_benchmark [--quick] [Google Benchmark flags]
//   --quick: smoke test, the comparison and one short run of each benchmark
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "datasets/synthetic/synthetic_dataset.h"
#include "mesh/mesh_renderer.h"
#include "tests/bench/agreement.h"

namespace sylva {
namespace {

constexpr int kImageSize = 256;
constexpr int kSamplesPerAxis = 4;

struct Scene {
  SyntheticTree tree;
  ImageSet image_set;
  MeshRenderer renderer;

  Scene()
      : tree(GenerateSyntheticTree(SyntheticTreeOptions(), 1)),
        image_set(MakeSyntheticCameras(Options(), tree.mesh)),
        renderer(tree.mesh) {}

  static SyntheticDatasetOptions Options() {
    SyntheticDatasetOptions options;
    options.image_size = kImageSize;
    return options;
  }
};

const Scene& GetScene() {
  static const Scene scene;
  return scene;
}

void SetRays(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations() * kImageSize * kImageSize * kSamplesPerAxis *
                          kSamplesPerAxis);
}

void BM_RenderCoverage(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    benchmark::DoNotOptimize(scene.renderer.RenderCoverage(
        scene.image_set.CameraOf(0), scene.image_set.views[0].cam_from_world, kSamplesPerAxis));
  }
  SetRays(state);
}
BENCHMARK(BM_RenderCoverage)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same picture from Embree's coherent ray streams, parallel over rows
// (what RenderCoverage did before it rasterized).
void BM_RenderCoverageRayStreams(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    benchmark::DoNotOptimize(scene.renderer.RenderCoverage(
        scene.image_set.CameraOf(0), scene.image_set.views[0].cam_from_world, kSamplesPerAxis,
        MeshRenderMethod::kRayCast));
  }
  SetRays(state);
}
BENCHMARK(BM_RenderCoverageRayStreams)->Unit(benchmark::kMillisecond)->UseRealTime();

// Reference: one CastRay per sample, single-threaded; the coverage image.
FloatImage ReferenceCoverage(const Scene& scene) {
  FloatImage coverage(kImageSize, kImageSize, 1, 0.0f);
  for (int row = 0; row < kImageSize; ++row) {
    for (int col = 0; col < kImageSize; ++col) {
      int hits = 0;
      for (int t = 0; t < kSamplesPerAxis; ++t) {
        for (int s = 0; s < kSamplesPerAxis; ++s) {
          const Eigen::Vector2d point(col + (s + 0.5) / kSamplesPerAxis,
                                      row + (t + 0.5) / kSamplesPerAxis);
          const Ray3d ray = scene.image_set.RayThroughPixel(0, point);
          hits += std::isfinite(scene.renderer.CastRay(ray)) ? 1 : 0;
        }
      }
      coverage.at(col, row) = static_cast<float>(hits) / (kSamplesPerAxis * kSamplesPerAxis);
    }
  }
  return coverage;
}

void BM_CastRayReference(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) benchmark::DoNotOptimize(ReferenceCoverage(scene));
  SetRays(state);
}
BENCHMARK(BM_CastRayReference)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GenerateSyntheticTree(benchmark::State& state) {
  for (auto _ : state) {
    benchmark::DoNotOptimize(GenerateSyntheticTree(SyntheticTreeOptions(), 1));
  }
}
BENCHMARK(BM_GenerateSyntheticTree)->Unit(benchmark::kMillisecond);

// Both cast the same rays at the same triangles, so the pictures should be
// equal but for rays grazing an edge, where Embree's stream and single-ray
// paths may round differently. Measured: mean and largest per-pixel
// coverage difference 0. TOLERANCES: at most 2 grazing rays of a pixel's 16,
// and on average no more than ~7 whole pixels of the 65,536.
constexpr double kMaxMeanCoverageDifference = 1e-4;
constexpr double kMaxPixelCoverageDifference = 2.0 / (kSamplesPerAxis * kSamplesPerAxis);

// Compares the fast picture with the reference's; false if they disagree.
bool CheckAgreement() {
  const Scene& scene = GetScene();
  const FloatImage fast = scene.renderer.RenderCoverage(
      scene.image_set.CameraOf(0), scene.image_set.views[0].cam_from_world, kSamplesPerAxis);
  const FloatImage reference = ReferenceCoverage(scene);
  double sum = 0.0, largest = 0.0;
  for (size_t i = 0; i < fast.values().size(); ++i) {
    const double difference = std::abs(fast.values()[i] - reference.values()[i]);
    sum += difference;
    largest = std::max(largest, difference);
  }
  const double mean = sum / fast.values().size();
  std::printf(
      "RenderCoverage vs CastRay reference, %d x %d pixels: mean |coverage difference| "
      "%.2e, largest %.4f\n",
      kImageSize, kImageSize, mean, largest);
  Agreement agreement;
  agreement.AtMost("mean |coverage difference| per pixel", mean, kMaxMeanCoverageDifference);
  agreement.AtMost("largest |coverage difference| of a pixel", largest,
                   kMaxPixelCoverageDifference);
  return agreement.ExitCode() == 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  std::vector<char*> args;
  bool quick = false;
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else {
      args.push_back(argv[i]);
    }
  }
  std::string short_runs = "--benchmark_min_time=0.01";  // one or a few iterations each
  if (quick) args.push_back(short_runs.data());
  int num_args = static_cast<int>(args.size());
  benchmark::Initialize(&num_args, args.data());
  if (benchmark::ReportUnrecognizedArguments(num_args, args.data())) return 2;
  if (!sylva::CheckAgreement()) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
