// Rendering the synthetic tree: MeshRenderer::RenderCoverage (coherent ray
// streams per row, parallel over rows) beside a simple reference that casts
// the same rays one by one through MeshRenderer::CastRay on one thread, so
// the ratio holds on a noisy machine. 256 x 256 pixels, 4 x 4 rays each.
#include <benchmark/benchmark.h>

#include <cmath>

#include "datasets/synthetic/synthetic_dataset.h"
#include "mesh/mesh_renderer.h"

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

// Reference: one CastRay per sample, single-threaded.
void BM_CastRayReference(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    double covered = 0.0;
    for (int row = 0; row < kImageSize; ++row) {
      for (int col = 0; col < kImageSize; ++col) {
        for (int t = 0; t < kSamplesPerAxis; ++t) {
          for (int s = 0; s < kSamplesPerAxis; ++s) {
            const Eigen::Vector2d point(col + (s + 0.5) / kSamplesPerAxis,
                                        row + (t + 0.5) / kSamplesPerAxis);
            const Ray3d ray = scene.image_set.RayThroughPixel(0, point);
            covered += std::isfinite(scene.renderer.CastRay(ray)) ? 1.0 : 0.0;
          }
        }
      }
    }
    benchmark::DoNotOptimize(covered);
  }
  SetRays(state);
}
BENCHMARK(BM_CastRayReference)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GenerateSyntheticTree(benchmark::State& state) {
  for (auto _ : state) {
    benchmark::DoNotOptimize(GenerateSyntheticTree(SyntheticTreeOptions(), 1));
  }
}
BENCHMARK(BM_GenerateSyntheticTree)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sylva

BENCHMARK_MAIN();
