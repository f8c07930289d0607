// Livewire attractor graphs on synthetic trees against their projected
// ground-truth skeletons: the by-hand measurement behind the seed-strategy
// and weight defaults of reconstruct/attractors/livewire.h.
//
//   sylva_livewire_probe [--out=DIR] [--trees=5] [--strategies=a,b,c]
//       [--num_seeds=8,16,24,32] [--weight_outside=W] [--weight_direction=W]
//       [--weight_centerline=W] [--photo_weight=W] [--max_order=2]
//
// For every synthetic tree (seeds 1..trees; 8 pinhole views of 512 px), every
// view is traced from the projection of the tree base (the world origin) and
// compared with ProjectSkeleton(max_order) sampled every pixel: Chamfer,
// coverage (mean truth -> graph) and precision (mean graph -> truth), in
// pixels and in % of the image size. With --out, overlays of the first tree's
// first three views for every strategy are written to DIR.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "datasets/eval/graph_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/attractors/overlay.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

struct ProbeFlags {
  std::string out;
  int trees = 5;
  int max_order = 2;
  std::vector<std::string> strategies = {"farthest_point", "skeleton_tips", "silhouette"};
  std::vector<int> num_seeds = {8, 16, 24, 32};
  LivewireOptions options;
};

std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream stream(list);
  for (std::string item; std::getline(stream, item, ',');) items.push_back(item);
  return items;
}

bool ApplyFlag(const std::string& name, const std::string& value, ProbeFlags* flags) {
  LivewireOptions& o = flags->options;
  if (name == "out")
    flags->out = value;
  else if (name == "trees")
    flags->trees = std::stoi(value);
  else if (name == "max_order")
    flags->max_order = std::stoi(value);
  else if (name == "strategies")
    flags->strategies = Split(value);
  else if (name == "num_seeds") {
    flags->num_seeds.clear();
    for (const std::string& n : Split(value)) flags->num_seeds.push_back(std::stoi(n));
  } else if (name == "weight_outside")
    o.weight_outside = std::stod(value);
  else if (name == "weight_direction")
    o.weight_direction = std::stod(value);
  else if (name == "weight_centerline")
    o.weight_centerline = std::stod(value);
  else if (name == "photo_weight")
    o.photo_weight = std::stod(value);
  else if (name == "simplify_tolerance")
    o.simplify_tolerance = std::stod(value);
  else
    return false;
  return true;
}

struct Totals {
  double chamfer = 0, coverage = 0, precision = 0, seconds = 0;
  int views = 0;
  void Add(const PointSetDistances& d, double s) {
    chamfer += d.chamfer, precision += d.mean_a_to_b, coverage += d.mean_b_to_a, seconds += s;
    ++views;
  }
};

void PrintRow(const std::string& strategy, int num_seeds, const Totals& t, double image_size) {
  const double n = t.views;
  std::printf("%-15s %5d %9.2f %7.2f%% %9.2f %9.2f %8.3f\n", strategy.c_str(), num_seeds,
              t.chamfer / n, 100 * t.chamfer / n / image_size, t.coverage / n, t.precision / n,
              t.seconds / n);
}

int Main(int argc, char** argv) {
  ProbeFlags flags;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const size_t eq = flag.find('=');
    if (flag.rfind("--", 0) != 0 || eq == std::string::npos ||
        !ApplyFlag(flag.substr(2, eq - 2), flag.substr(eq + 1), &flags)) {
      std::fprintf(stderr, "unknown flag %s (see the file comment)\n", flag.c_str());
      return 2;
    }
  }
  std::vector<SyntheticDataset> datasets;
  SyntheticDatasetOptions data_options;
  data_options.num_held_out = 0;
  for (int tree = 1; tree <= flags.trees; ++tree) {
    data_options.seed = tree;
    datasets.push_back(MakeSyntheticDataset(data_options));
  }
  const double image_size = data_options.image_size;
  std::printf(
      "%d trees x %d views, %d px; truth = skeleton orders <= %d; weights outside %.2f "
      "direction %.2f centreline %.2f photo %.2f\n",
      flags.trees, data_options.num_views, data_options.image_size, flags.max_order,
      flags.options.weight_outside, flags.options.weight_direction, flags.options.weight_centerline,
      flags.options.photo_weight);
  std::printf("%-15s %5s %9s %8s %9s %9s %8s\n", "strategy", "seeds", "chamfer", "%size",
              "coverage", "precision", "s/view");
  if (!flags.out.empty()) std::filesystem::create_directories(flags.out);
  for (const std::string& strategy : flags.strategies) {
    for (const int num_seeds : flags.num_seeds) {
      LivewireOptions options = flags.options;
      options.seeds = strategy;
      options.num_seeds = num_seeds;
      Totals totals;
      for (size_t t = 0; t < datasets.size(); ++t) {
        const SyntheticDataset& data = datasets[t];
        for (int v = 0; v < data.image_set.NumViews(); ++v) {
          Eigen::Vector2d target;
          data.image_set.Project(v, Eigen::Vector3d::Zero(), &target);
          LivewireSummary summary;
          const AttractorGraph2D graph =
              TraceAttractorGraph(data.photos[v], data.mattes[v], target, {}, options, &summary);
          const AttractorGraph2D truth =
              ProjectSkeleton(data.tree.skeleton, data.image_set, v, flags.max_order);
          totals.Add(CompareGraphs2D(graph, truth, 1.0), summary.seconds);
          if (!flags.out.empty() && t == 0 && v < 3 && num_seeds == flags.num_seeds.back()) {
            WriteImage(std::filesystem::path(flags.out) /
                           (strategy + "_view" + std::to_string(v) + ".png"),
                       DrawAttractorOverlay(data.photos[v], graph));
            WriteImage(
                std::filesystem::path(flags.out) / ("truth_view" + std::to_string(v) + ".png"),
                DrawAttractorOverlay(data.photos[v], truth));
          }
        }
      }
      PrintRow(strategy, num_seeds, totals, image_size);
    }
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
