// By hand: how much attractor graphs steer the skeleton towards the truth on
// synthetic trees. For each tree seed: the density from 8 views, then the
// skeleton without a direction field and with the field of the true main
// branches (orders <= --graph_order) projected into every input view; prints
// the 2D Chamfer distance between the projected skeletons' main branches
// (orders 0-2) in pixels, the 3D skeleton Chamfer (% of height) and the mesh
// silhouette IoU.
//   sylva_attractor_probe [--seeds=1,2,3,4,5] [--graphs=truth|livewire]
//       [--our_order=2] [--name=value ...]
// --our_order: the orders of our skeleton compared with the true main
// branches (99: all of it, which tells a worse order assignment from worse
// geometry).
// with names of DirectionField.* / ParticleFlow.* options (e.g.
// --DirectionField.falloff=0.05 --ParticleFlow.field_weight=2).
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/util/check.h"
#include "core/util/random.h"
#include "datasets/eval/graph_metrics.h"
#include "datasets/eval/point_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/density/density_reconstruction.h"
#include "simulate/particle_flow.h"
#include "tests/bench/probe_main.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

struct Result {
  double chamfer_2d_px = 0, ours_to_truth = 0, truth_to_ours = 0, chamfer_3d = 0, mean_iou = 0,
         min_iou = 1;
};

// Orders of our skeleton projected for the 2D comparison (--our_order).
int our_order = 2;

Result Evaluate(const SyntheticDataset& data, const BuiltSkeleton& built,
                const DensityGrid& density, const PipelineOptions& options) {
  Result result;
  const ImageSet inputs = data.InputImageSet();
  const std::vector<FloatImage> mattes = data.InputMattes();
  for (int v = 0; v < inputs.NumViews(); ++v) {
    const PointSetDistances d =
        CompareGraphs2D(ProjectSkeleton(built.skeleton, inputs, v, our_order),
                        ProjectSkeleton(data.tree.skeleton, inputs, v, 2), 1.0);
    result.chamfer_2d_px += d.chamfer / inputs.NumViews();
    result.ours_to_truth += d.mean_a_to_b / inputs.NumViews();
    result.truth_to_ours += d.mean_b_to_a / inputs.NumViews();
  }
  const double height = data.tree.mesh.Bounds().max().z();
  const double spacing = 0.005 * height;
  result.chamfer_3d = ComparePointSets(built.skeleton.SamplePoints(spacing),
                                       data.tree.skeleton.SamplePoints(spacing))
                          .chamfer /
                      height;
  std::string brief;
  const TriangleMesh mesh = BuildTreeMesh(built.skeleton, density, inputs, mattes, options, &brief);
  ReportOptions report_options;
  report_options.write_images = false;
  FidelityReport report =
      ComputeFidelity(density, data.image_set, data.mattes, data.HeldOutFlags(), report_options);
  AddMeshFidelity(mesh, data.image_set, report_options, &report);
  int n = 0;
  for (const ViewFidelity& view : report.views) {
    if (view.held_out) continue;
    result.mean_iou += view.mesh_scores.iou;
    result.min_iou = std::min(result.min_iou, view.mesh_scores.iou);
    ++n;
  }
  result.mean_iou /= n;
  return result;
}

int Main(int argc, char** argv) {
  std::vector<uint64_t> seeds = {1, 2, 3, 4, 5};
  int graph_order = 2;
  bool livewire = false;  // --graphs=livewire: traced graphs, else the truth projected
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const size_t eq = flag.find('=');
    SYLVA_CHECK_INPUT(flag.rfind("--", 0) == 0 && eq != std::string::npos, flag)
        << "expected --name=value";
    const std::string name = flag.substr(2, eq - 2), value = flag.substr(eq + 1);
    if (name == "seeds") {
      seeds.clear();
      std::stringstream list(value);
      std::string item;
      while (std::getline(list, item, ',')) seeds.push_back(std::stoull(item));
    } else if (name == "graphs") {
      livewire = value == "livewire";
    } else if (name == "graph_order") {
      graph_order = std::stoi(value);
    } else if (name == "our_order") {
      our_order = std::stoi(value);
    } else {
      registry.Set(name, value, "command line");
    }
  }
  options.Check();
  Result sum_without, sum_with;
  for (uint64_t seed : seeds) {
    SyntheticDatasetOptions synth;
    synth.seed = seed;
    synth.num_views = 8;
    synth.num_held_out = 0;
    const SyntheticDataset data = MakeSyntheticDataset(synth);
    const ImageSet inputs = data.InputImageSet();
    const std::vector<FloatImage> mattes = data.InputMattes();
    const DensityGrid density =
        ReconstructDensity(inputs, mattes, options.density, nullptr, nullptr);
    std::vector<AttractorGraph2D> graphs;
    const Eigen::Vector3d base = EstimateTreeBase(density, options.tree_base);
    LivewireOptions livewire_options = options.attract.livewire;
    livewire_options.seed = DeriveSeed(seed, 3);
    for (int v = 0; v < inputs.NumViews(); ++v) {
      Eigen::Vector2d target;
      inputs.Project(v, base, &target);
      graphs.push_back(
          livewire ? TraceAttractorGraph(data.photos[v], mattes[v], target, {}, livewire_options)
                   : ProjectSkeleton(data.tree.skeleton, inputs, v, graph_order));
    }
    const BuiltSkeleton without = BuildSkeleton(density, inputs, mattes, {}, options, nullptr);
    const BuiltSkeleton with = BuildSkeleton(density, inputs, mattes, graphs, options, nullptr);
    const Result a = Evaluate(data, without, density, options);
    const Result b = Evaluate(data, with, density, options);
    std::printf(
        "seed %d: 2D Chamfer %.2f -> %.2f px (%+.0f %%), 3D Chamfer %.2f -> %.2f %% of height, "
        "mesh IoU mean %.3f -> %.3f, min %.3f -> %.3f; ours->truth %.2f -> %.2f, truth->ours %.2f "
        "-> %.2f\n",
        static_cast<int>(seed), a.chamfer_2d_px, b.chamfer_2d_px,
        100 * (b.chamfer_2d_px / a.chamfer_2d_px - 1), 100 * a.chamfer_3d, 100 * b.chamfer_3d,
        a.mean_iou, b.mean_iou, a.min_iou, b.min_iou, a.ours_to_truth, b.ours_to_truth,
        a.truth_to_ours, b.truth_to_ours);
    std::fflush(stdout);
    sum_without.chamfer_2d_px += a.chamfer_2d_px / seeds.size();
    sum_with.chamfer_2d_px += b.chamfer_2d_px / seeds.size();
    sum_without.chamfer_3d += a.chamfer_3d / seeds.size();
    sum_with.chamfer_3d += b.chamfer_3d / seeds.size();
  }
  std::printf("mean: 2D Chamfer %.2f -> %.2f px (%+.1f %%), 3D Chamfer %.2f -> %.2f %% of height\n",
              sum_without.chamfer_2d_px, sum_with.chamfer_2d_px,
              100 * (sum_with.chamfer_2d_px / sum_without.chamfer_2d_px - 1),
              100 * sum_without.chamfer_3d, 100 * sum_with.chamfer_3d);
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
