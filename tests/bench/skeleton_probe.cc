// By hand: how much wood the skeleton carries against the truth on synthetic
// trees (issue 12, item 5). For each tree seed, leafless (no leaf clusters)
// and leafy: the density from 8 views, livewire attractor graphs as the
// attract stage traces them, the skeleton as the skeleton stage builds it,
// then CompareSkeletons against the generator's skeleton: total length
// ratio, precision and recall (within 2 % of the height), Chamfer, axes per
// order, and the length traced twice (within 1 % of the height of our own
// wood on another branch; the ratio without it).
//   sylva_skeleton_probe [--seeds=1,2,3,4,5] [--trees=leafless,leafy]
//       [--qsm=A.csv,B.csv] [--graphs=livewire|none] [--out=DIR] [--name=value ...]
// --qsm: laser-scanned trees' QSM tables (e.g. datasets/itsme-qsm/*.csv),
// each meshed as mesh-qsm does and rendered from the synthetic views; the
// table's largest part is the true skeleton (--trees= leaves out the
// generated trees).
// with names of pipeline options (e.g. --ParticleFlow.num_particles=2000).
// Or compares two skeleton files (e.g. a project's out/skeleton.json with a
// synthetic set's ground_truth/skeleton.json):
//   sylva_skeleton_probe --compare=OURS.json,TRUTH.json
// --out=DIR writes DIR/<kind>_<seed>_{ours,truth}.json and
// DIR/<kind>_<seed>_samples.csv: points every voxel along our skeleton with
// their strands, the density's opacity there, the occupied share of the
// 5 x 5 x 5 voxels around and the distance to the true skeleton (what tells
// wrong wood from right).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/geometry/point_grid.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "datasets/eval/skeleton_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "tests/bench/probe_main.h"
#include "tests/fidelity/qsm_photos.h"
#include "tests/fidelity/synthetic_livewire.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

std::vector<std::string> SplitList(const std::string& value) {
  std::vector<std::string> items;
  std::stringstream list(value);
  std::string item;
  while (std::getline(list, item, ',')) items.push_back(item);
  return items;
}

void WriteSamples(const std::string& path, const SkeletonGraph& ours, const SkeletonGraph& truth,
                  const DensityGrid& density) {
  const double spacing = density.voxel_size();
  const PointGrid true_points(truth.SamplePoints(0.25 * spacing));
  std::ofstream out(path);
  out << "x,y,z,strands,opacity,occupancy,distance\n";
  for (const SkeletonNode& node : ours.nodes) {
    if (node.parent_idx < 0) continue;
    const Eigen::Vector3d& parent = ours.nodes[node.parent_idx].position;
    const int steps =
        std::max(1, static_cast<int>(std::ceil((node.position - parent).norm() / spacing)));
    for (int s = 0; s < steps; ++s) {
      const Eigen::Vector3d p = parent + (node.position - parent) * ((s + 0.5) / steps);
      const Eigen::Vector3i ijk = density.IndexFromWorld(p).array().round().cast<int>();
      int occupied = 0;
      for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx)
            occupied += density.Value(ijk + Eigen::Vector3i(dx, dy, dz)) > 0.05f;
      double distance = 0;
      true_points.Nearest(p, 1e300, &distance);
      out << p.x() << "," << p.y() << "," << p.z() << "," << node.strands << ","
          << density.Value(ijk) << "," << occupied / 125.0 << "," << distance << "\n";
    }
  }
}

// Mean figures over the trees of one kind.
struct ProbeSums {
  int trees = 0;
  double ratio = 0, ratio_once = 0, precision = 0, recall = 0, chamfer = 0;

  void Add(const SkeletonComparison& c) {
    ++trees;
    ratio += c.length_ratio;
    ratio_once += c.length_ratio_once;
    precision += c.precision;
    recall += c.recall;
    chamfer += c.chamfer_fraction;
  }
  void Print(const std::string& kind) const {
    if (trees == 0) return;
    std::printf(
        "%-8s mean: length %.2f x truth (%.2f x traced once), precision %.3f, recall %.3f, "
        "Chamfer %.2f %%\n",
        kind.c_str(), ratio / trees, ratio_once / trees, precision / trees, recall / trees,
        100 * chamfer / trees);
  }
};

// Reconstructs the skeleton of a rendered dataset as the stages would and
// compares it with the dataset's true skeleton.
SkeletonComparison ProbeTree(const std::string& label, const SyntheticDataset& data,
                             const PipelineOptions& options, bool livewire,
                             const std::string& out) {
  const ImageSet inputs = data.InputImageSet();
  const std::vector<FloatImage> mattes = data.InputMattes();
  const DensityGrid density = ReconstructDensity(inputs, mattes, options.density, nullptr, nullptr);
  const std::vector<AttractorGraph2D> graphs =
      livewire ? SyntheticLivewireGraphs(data, inputs, mattes, density, options)
               : std::vector<AttractorGraph2D>();
  const BuiltSkeleton built = BuildSkeleton(density, inputs, mattes, graphs, options, nullptr);
  const SkeletonGraph& truth = data.tree.skeleton;
  const SkeletonComparison c = CompareSkeletons(built.skeleton, truth, truth.Height());
  std::printf("%s: %s\n", label.c_str(), c.BriefReport().c_str());
  std::fflush(stdout);
  if (!out.empty()) {
    const std::string stem = out + "/" + label;
    WriteSkeletonJson(stem + "_ours.json", built.skeleton, "m");
    WriteSkeletonJson(stem + "_truth.json", truth, "m");
    WriteSamples(stem + "_samples.csv", built.skeleton, truth, density);
  }
  return c;
}

int Main(int argc, char** argv) {
  std::vector<uint64_t> seeds = {1, 2, 3, 4, 5};
  std::vector<std::string> trees = {"leafless", "leafy"}, qsm_files;
  bool livewire = true;
  std::string out;
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
      for (const std::string& item : SplitList(value)) seeds.push_back(std::stoull(item));
    } else if (name == "trees") {
      trees = value.empty() ? std::vector<std::string>() : SplitList(value);
    } else if (name == "qsm") {
      qsm_files = SplitList(value);
    } else if (name == "graphs") {
      livewire = value == "livewire";
    } else if (name == "compare") {
      const std::vector<std::string> files = SplitList(value);
      SYLVA_CHECK_INPUT(files.size() == 2, "--compare") << "expected OURS.json,TRUTH.json";
      const SkeletonGraph ours = ReadSkeletonJson(files[0]), truth = ReadSkeletonJson(files[1]);
      std::printf("%s\n", CompareSkeletons(ours, truth, truth.Height()).BriefReport().c_str());
      return 0;
    } else if (name == "out") {
      out = value;
    } else {
      registry.Set(name, value, "command line");
    }
  }
  options.Check();
  if (!out.empty()) std::filesystem::create_directories(out);
  SyntheticDatasetOptions views;
  views.num_views = 8;
  views.num_held_out = 0;
  for (const std::string& kind : trees) {
    SYLVA_CHECK_INPUT(kind == "leafless" || kind == "leafy", "--trees") << "unknown tree " << kind;
    ProbeSums sums;
    for (uint64_t seed : seeds) {
      SyntheticDatasetOptions synth = views;
      synth.seed = seed;
      if (kind == "leafless") synth.tree.leaves_per_cluster = 0;
      const std::string label = kind + "_" + std::to_string(seed);
      sums.Add(ProbeTree(label, MakeSyntheticDataset(synth), options, livewire, out));
    }
    sums.Print(kind);
  }
  ProbeSums qsm_sums;
  for (const std::string& file : qsm_files) {
    const std::string label = "qsm_" + std::filesystem::path(file).stem().string();
    qsm_sums.Add(ProbeTree(label, QsmPhotoDataset(file, views, options), options, livewire, out));
  }
  qsm_sums.Print("qsm");
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
