// The skeleton stage (thesis 3.4 and 5.1): density -> particle flow to the
// tree base -> skeleton with pipe-model radii scaled to the trunk width seen
// in the mattes. Writes out/skeleton.json, out/skeleton.ply (AdTree layout)
// and out/skeleton_raw.json (the traces before simplification).
#include <algorithm>
#include <sstream>

#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/util/logging.h"
#include "core/util/random.h"
#include "mesh/allometry.h"
#include "mesh/trunk_width.h"
#include "simulate/direction_field.h"
#include "simulate/particle_flow.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

// Stream ids for DeriveSeed(General.seed, stream).
constexpr uint64_t kParticleSeedStream = 1;

double SkeletonHeight(const SkeletonGraph& skeleton, const Eigen::Vector3d& base) {
  double top = base.z();
  for (const SkeletonNode& node : skeleton.nodes) top = std::max(top, node.position.z());
  return top - base.z();
}

// The trunk radius: the option, or measured in the mattes, or a fraction of
// the height; `how` says which.
double TrunkRadius(const StageContext& context, const Eigen::Vector3d& base, double height,
                   std::string* how) {
  const SkeletonOptions& options = context.options.skeleton;
  if (options.trunk_radius > 0) {
    *how = "given";
    return options.trunk_radius;
  }
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "skeleton: reading mattes");
  const TrunkWidth width = MeasureTrunkWidth(views, mattes, base, height);
  if (width.radius > 0) {
    *how = "measured in " + std::to_string(width.num_measurements) + " matte sections";
    return width.radius;
  }
  *how = "not measurable in the mattes; " + std::to_string(options.trunk_radius_fraction) +
         " x height";
  return options.trunk_radius_fraction * height;
}

}  // namespace

StageRun RunSkeletonStage(const StageContext& context) {
  const PipelineOptions& options = context.options;
  const DensityGrid density = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const Eigen::Vector3d base = options.skeleton.base.allFinite()
                                   ? options.skeleton.base
                                   : EstimateTreeBase(density, options.tree_base);
  ParticleFlowOptions flow = options.particle_flow;
  flow.seed = DeriveSeed(options.general.seed, kParticleSeedStream);
  ParticleFlowSummary flow_summary;
  SkeletonGraph raw;
  SkeletonGraph skeleton = SimulateParticleFlow(density, base, ConstantDirectionField(), flow,
                                                context.progress, &flow_summary, &raw);
  const double height = SkeletonHeight(skeleton, base);
  std::string how;
  AllometryOptions allometry = options.allometry;
  allometry.trunk_radius = TrunkRadius(context, base, std::max(height, density.voxel_size()), &how);
  allometry.min_radius = options.skeleton.min_radius_fraction * allometry.trunk_radius;
  AssignPipeModelRadii(allometry, &skeleton);

  const std::string& units = context.project.units();
  StageRun run;
  std::ostringstream brief;
  brief << flow_summary.BriefReport() << " Base (" << base.transpose() << "); trunk radius "
        << allometry.trunk_radius << " (" << how << "; radii are an allometric prior, Delta "
        << allometry.diameter_exponent << ").";
  run.brief = brief.str();
  run.outputs = {context.Out("skeleton.json"), context.Out("skeleton.ply"),
                 context.Out("skeleton_raw.json")};
  WriteSkeletonJson(run.outputs[0], skeleton, units);
  WriteSkeletonPly(run.outputs[1], skeleton, units);
  WriteSkeletonJson(run.outputs[2], raw, units);
  return run;
}

}  // namespace sylva
