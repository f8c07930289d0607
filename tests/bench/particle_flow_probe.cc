// Runs the particle flow on a density grid and compares its skeleton with a
// ground-truth skeleton: the by-hand check of the skeleton's fidelity on
// synthetic trees (how the defaults in simulate/particle_flow.h were tuned).
//
//   sylva synth T --seed 1
//   sylva init P --photos T/photos --mattes T/mattes --cameras T/cameras.json
//       --held-out @T/held_out.txt
//   sylva run P
//   sylva_particle_flow_probe P/out/density.vdb T/ground_truth/skeleton.json
//       [--seed=N] [--num_particles=N] [--descent_angle_deg=D] [--out=skeleton.json]
// (each command on one line).
//
// The base is estimated from the density (EstimateTreeBase); the true base
// of a synthetic tree is the origin. Both skeletons are sampled every voxel
// along their edges; distances are reported relative to the true tree's
// height (the targets: Chamfer <= 5 %, root within 2 % of the height).
#include <cstdio>
#include <cstring>
#include <string>

#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/util/check.h"
#include "datasets/eval/point_metrics.h"
#include "simulate/particle_flow.h"

namespace sylva {
namespace {

// Applies one --name=value flag; false if unknown.
bool ApplyFlag(const std::string& name, const std::string& value, ParticleFlowOptions* options,
               std::string* out) {
  if (name == "seed")
    options->seed = std::stoull(value);
  else if (name == "num_particles")
    options->num_particles = std::stoi(value);
  else if (name == "descent_angle_deg")
    options->descent_angle_deg = std::stod(value);
  else if (name == "neighbor_radius")
    options->neighbor_radius = std::stod(value);
  else if (name == "neighbor_pull")
    options->neighbor_pull = std::stod(value);
  else if (name == "join_finished_traces")
    options->join_finished_traces = value == "1";
  else if (name == "join_flowing_traces")
    options->join_flowing_traces = value == "1";
  else if (name == "out")
    *out = value;
  else
    return false;
  return true;
}

int Main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s DENSITY.vdb TRUE_SKELETON.json [--name=value ...]\n", argv[0]);
    return 2;
  }
  ParticleFlowOptions options;
  std::string out;
  for (int i = 3; i < argc; ++i) {
    const std::string flag = argv[i];
    const size_t equals = flag.find('=');
    if (flag.rfind("--", 0) != 0 || equals == std::string::npos ||
        !ApplyFlag(flag.substr(2, equals - 2), flag.substr(equals + 1), &options, &out)) {
      std::fprintf(stderr, "unknown flag %s\n", flag.c_str());
      return 2;
    }
  }
  const DensityGrid density = ReadDensityGrid(argv[1]);
  const SkeletonGraph truth = ReadSkeletonJson(argv[2]);
  const Eigen::Vector3d base = EstimateTreeBase(density);
  ParticleFlowSummary summary;
  const SkeletonGraph skeleton =
      SimulateParticleFlow(density, base, ConstantDirectionField(), options, nullptr, &summary);
  double height = 0.0;
  for (const SkeletonNode& node : truth.nodes) height = std::max(height, node.position.z());
  const double spacing = density.voxel_size();
  const PointSetDistances d =
      ComparePointSets(skeleton.SamplePoints(spacing), truth.SamplePoints(spacing));
  const std::vector<std::vector<int>> children = skeleton.Children();
  int trunk = 0;
  for (int child : children[0]) trunk = std::max(trunk, skeleton.nodes[child].strands);
  std::printf("%s\n", summary.BriefReport().c_str());
  std::printf(
      "height %.2f, voxel %.4f; root error %.2f%% of height; Chamfer %.2f%% "
      "(ours->truth %.2f%%, truth->ours %.2f%%), Hausdorff %.1f%%; trunk carries %d of "
      "%d particles\n",
      height, spacing, 100 * base.norm() / height, 100 * d.chamfer / height,
      100 * d.mean_a_to_b / height, 100 * d.mean_b_to_a / height, 100 * d.hausdorff / height, trunk,
      options.num_particles);
  if (!out.empty()) WriteSkeletonJson(out, skeleton, "m");
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    return sylva::Main(argc, argv);
  } catch (const sylva::Error& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  }
}
