// By hand: the density's fit against the least-squares solver's iteration
// count, on the synthetic trees (8 input views, 2 held out): the input and
// held-out views' silhouette IoU (mean / min), the residual, the solve's
// time and the voxels stored, with and without Cauchy steps.
//
// usage: sylva_density_iterations_probe [--trees=N] [--iterations=10,20,...]
//                                       [--cauchy_every=K[,K...]]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/util/memory.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/report.h"

namespace sylva {
namespace {

std::vector<int> ParseList(const char* text) {
  std::vector<int> values;
  for (const char* c = text; *c;) {
    char* end = nullptr;
    values.push_back(static_cast<int>(std::strtol(c, &end, 10)));
    if (end == c) break;
    c = *end ? end + 1 : end;
  }
  return values;
}

int Main(int argc, char** argv) {
  int trees = 5;
  std::vector<int> counts = {10, 20, 30, 40, 50, 80};
  std::vector<int> cauchy = {0, 3};
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--trees=", 8) == 0) {
      trees = std::atoi(argv[i] + 8);
    } else if (std::strncmp(argv[i], "--iterations=", 13) == 0) {
      counts = ParseList(argv[i] + 13);
    } else if (std::strncmp(argv[i], "--cauchy_every=", 15) == 0) {
      cauchy = ParseList(argv[i] + 15);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--trees=N] [--iterations=10,20,...] [--cauchy_every=K,...]\n",
                   argv[0]);
      return 2;
    }
  }
  std::printf("%4s %6s %5s %9s %15s %15s %8s %8s\n", "tree", "cauchy", "it", "|r|",
              "input mean/min", "held-out m/min", "solve s", "voxels");
  for (int seed = 1; seed <= trees; ++seed) {
    SyntheticDatasetOptions synth;
    synth.seed = seed;
    synth.num_views = 8;
    synth.num_held_out = 2;
    const SyntheticDataset data = MakeSyntheticDataset(synth);
    for (int every : cauchy) {
      for (int n : counts) {
        DensityOptions options;
        options.max_iterations = n;
        options.cauchy_every = every;
        DensitySummary summary;
        const DensityGrid grid = ReconstructDensity(data.InputImageSet(), data.InputMattes(),
                                                    options, nullptr, &summary);
        const FidelityReport report = ComputeFidelity(grid, data.image_set, data.mattes,
                                                      data.HeldOutFlags(), ReportOptions());
        std::printf("%4d %6d %5d %9.4f  %6.4f/%6.4f  %6.4f/%6.4f %8.3f %8lld\n", seed, every,
                    summary.solves.back().iterations, summary.solves.back().final_residual_norm,
                    *report.input.mean_iou, *report.input.min_iou, *report.held_out.mean_iou,
                    *report.held_out.min_iou, summary.seconds_solve,
                    static_cast<long long>(summary.num_output_voxels));
        std::fflush(stdout);
      }
    }
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  sylva::KeepFreedMemoryForReuse();
  return sylva::Main(argc, argv);
}
