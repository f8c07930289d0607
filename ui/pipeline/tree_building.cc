#include "ui/pipeline/tree_building.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <memory>
#include <sstream>

#include "core/util/check.h"
#include "core/util/random.h"
#include "mesh/allometry.h"
#include "mesh/leaves.h"
#include "mesh/subdivision.h"
#include "mesh/trunk_width.h"
#include "mesh/wood.h"
#include "reconstruct/measurement/branch_width.h"
#include "simulate/attractor_field.h"
#include "simulate/direction_field.h"
#include "simulate/particle_flow.h"
#include "simulate/skeleton_consolidation.h"
#include "simulate/skeleton_pruning.h"

namespace sylva {
namespace {

// Stream ids for DeriveSeed(General.seed, stream).
constexpr uint64_t kParticleSeedStream = 1;
constexpr uint64_t kLeafSeedStream = 2;
constexpr uint64_t kTwigSeedStream = 4;  // 3: the attract stage's livewire

}  // namespace

BuiltSkeleton BuildSkeleton(const DensityGrid& density, const ImageSet& input_views,
                            const std::vector<FloatImage>& mattes,
                            const std::vector<AttractorGraph2D>& attractors,
                            const PipelineOptions& options, ProgressReporter* progress,
                            const std::vector<FloatImage>* painted_in) {
  BuiltSkeleton built;
  StepClock clock(&built.profile);
  built.base = options.skeleton.base.allFinite() ? options.skeleton.base
                                                 : EstimateTreeBase(density, options.tree_base);
  clock.Lap("base");
  ParticleFlowOptions flow = options.particle_flow;
  flow.seed = DeriveSeed(options.general.seed, kParticleSeedStream);
  const bool steered = std::any_of(attractors.begin(), attractors.end(),
                                   [](const AttractorGraph2D& graph) { return !graph.IsEmpty(); });
  std::unique_ptr<DirectionField> field;
  std::string field_brief = "No attractor graphs (the flow follows the density alone).";
  if (steered) {
    Eigen::AlignedBox3d bounds = density.ActiveWorldBounds();
    bounds.extend(built.base);
    auto attractor_field = std::make_unique<AttractorDirectionField>(
        input_views, attractors, bounds, options.direction_field, progress);
    std::ostringstream text;
    text << "Direction field from the attractor graphs of " << attractor_field->NumViewsWithGraphs()
         << " of " << input_views.NumViews() << " views (" << options.direction_field.blend
         << " blend, " << options.direction_field.combine << ", weight " << flow.field_weight
         << ").";
    field_brief = text.str();
    field = std::move(attractor_field);
  } else {
    field = std::make_unique<ConstantDirectionField>();
  }
  clock.Lap("direction_field");
  ParticleFlowSummary flow_summary;
  const SkeletonGraph flowed =
      SimulateParticleFlow(density, built.base, *field, flow, progress, &flow_summary, &built.raw);
  clock.Lap("particle_flow")
      .Add("seed", flow_summary.seconds_seed)
      .Add("neighbors", flow_summary.seconds_neighbors)
      .Add("join", flow_summary.seconds_join)
      .Add("integrate", flow_summary.seconds_integrate)
      .Add("skeleton", flow_summary.seconds_skeleton);
  const std::vector<FloatImage> none(painted_in == nullptr ? input_views.NumViews() : 0);
  const PaintedDensity painted(density, input_views, painted_in == nullptr ? none : *painted_in);
  MattePruningSummary pruning;
  const SkeletonGraph pruned = PruneBranchesOutsideMattes(
      flowed, input_views, mattes, options.skeleton.pruning, &pruning, &painted);
  clock.Lap("prune");
  ConsolidationSummary consolidation;
  built.skeleton = ConsolidateSkeleton(pruned, density, options.skeleton.consolidation,
                                       &consolidation, &painted);
  clock.Lap("consolidate");
  const double height = std::max(built.skeleton.Height(), density.voxel_size());
  const TrunkRadius trunk = ChooseTrunkRadius(
      input_views, mattes, built.skeleton, height, options.skeleton.trunk_radius,
      options.skeleton.trunk_radius_fraction, options.allometry.diameter_exponent);
  AllometryOptions allometry = options.allometry;
  allometry.trunk_radius = trunk.radius;
  allometry.min_radius = options.skeleton.min_radius_fraction * allometry.trunk_radius;
  AssignPipeModelRadii(allometry, &built.skeleton);
  std::string widths = "Radii are an allometric prior.";
  if (!mattes.empty()) {
    const BranchWidthSummary summary = MeasureBranchRadii(
        input_views, mattes, options.leaves.num_leaves<0, options.skeleton.trunk_radius> 0,
        options.branch_width, &built.skeleton);
    if (summary.measured_axes > 0) widths = summary.BriefReport();
  }
  if (options.skeleton.consolidation.remove_hidden_twigs) {
    consolidation.hidden_twigs = RemoveHiddenTwigs(
        options.skeleton.consolidation.sample_spacing_fraction * height, &built.skeleton);
    consolidation.length_after = built.skeleton.TotalLength();
  }
  clock.Lap("radii");
  built.trunk_radius = built.skeleton.nodes.empty()
                           ? allometry.trunk_radius
                           : built.skeleton.nodes[built.skeleton.RootIdx()].radius;
  std::ostringstream brief;
  brief << field_brief << " " << flow_summary.BriefReport() << " " << pruning.BriefReport() << " "
        << consolidation.BriefReport() << " Base (" << built.base.transpose() << "); trunk radius "
        << allometry.trunk_radius << " (" << trunk.how << "; pipe model, Delta "
        << allometry.diameter_exponent << "). " << widths;
  built.brief = brief.str();
  return built;
}

WoodOptions WoodOptionsOf(const PipelineOptions& options) {
  WoodOptions wood;
  wood.watertight_bark = options.geometry.watertight_bark;
  wood.bark = options.geometry.bark;
  wood.bark.tube = options.branch_mesh;
  wood.twigs = options.geometry.twigs;
  wood.twig = options.geometry.twig;
  wood.twig.seed = DeriveSeed(options.general.seed, kTwigSeedStream);
  wood.twig_mesh = options.geometry.twig_mesh;
  return wood;
}

LeafOptions LeafOptionsOf(const PipelineOptions& options) {
  LeafOptions leaves = options.leaves;
  leaves.seed = DeriveSeed(options.general.seed, kLeafSeedStream);
  return leaves;
}

TriangleMesh TreeGeometry::Wood() const {
  TriangleMesh mesh = bark;
  if (twigs.NumTriangles() > 0) mesh.Append(twigs);
  return mesh;
}

TriangleMesh TreeGeometry::Baked() const {
  TriangleMesh mesh = Wood();
  if (!leaves.instances.empty()) mesh.Append(leaves.Bake());
  return mesh;
}

TreeGeometry BuildTreeGeometry(const SkeletonGraph& skeleton, const DensityGrid& density,
                               const ImageSet& input_views, const std::vector<FloatImage>& mattes,
                               const PipelineOptions& options, const LeafShape* shape) {
  TreeGeometry geometry;
  StepClock clock(&geometry.profile);
  const WoodOptions wood_options = WoodOptionsOf(options);
  const GrownSkeleton grown = GrowWoodSkeleton(skeleton, density, wood_options);
  if (wood_options.twigs) clock.Lap("twigs");
  // The bark and the leaves are independent (each deterministic, the leaves
  // with their own random stream) and mostly serial: made side by side.
  const LeafOptions leaf_options = LeafOptionsOf(options);
  const bool leafless = leaf_options.num_leaves < 0;
  LeafSummary leaf_summary;
  double wood_seconds = 0.0, leaf_seconds = 0.0;
  std::ostringstream wood_brief;
  tbb::parallel_invoke(
      [&] {
        wood_seconds = TimeOf([&] {
          Wood wood = MeshGrownWood(grown, wood_options);  // a copy: the leaves read `grown`
          geometry.bark = std::move(wood.bark);
          geometry.twigs = std::move(wood.twigs);
          geometry.bark_summary = wood.bark_summary;
          wood_brief << wood.brief;
          SubdivideBark(options.geometry, &geometry.bark, &wood_brief);
        });
      },
      [&] {
        if (leafless) return;
        leaf_seconds = TimeOf([&] {
          geometry.leaves = GenerateLeafInstances(grown.skeleton, density, input_views, mattes,
                                                  leaf_options, &leaf_summary, shape);
        });
      });
  StageStep& both = clock.Lap("wood_and_leaves");  // side by side: their times overlap
  both.Add("wood", wood_seconds);
  if (!leafless) both.Add("leaves", leaf_seconds);
  std::ostringstream brief;
  brief << wood_brief.str();
  if (leafless) {
    brief << " No leaves (Leaves.num_leaves=-1).";
  } else {
    brief << " " << leaf_summary.BriefReport();
  }
  geometry.brief = brief.str();
  return geometry;
}

void SubdivideBark(const TreeGeometryOptions& options, TriangleMesh* bark, std::ostream* brief) {
  if (options.bark_subdivision == 0) return;
  LoopSubdivisionSummary summary;
  try {
    *bark = SubdivideLoop(*bark, options.bark_subdivision, &summary);
  } catch (const InputError& error) {
    SYLVA_INPUT_ERROR("BranchMesh.subdivision")
        << "cannot subdivide the bark (" << error.message() << "); set BranchMesh.subdivision=0";
  }
  *brief << " " << summary.BriefReport();
}

TriangleMesh BuildTreeMesh(const SkeletonGraph& skeleton, const DensityGrid& density,
                           const ImageSet& input_views, const std::vector<FloatImage>& mattes,
                           const PipelineOptions& options, std::string* brief) {
  const TreeGeometry geometry = BuildTreeGeometry(skeleton, density, input_views, mattes, options);
  if (brief != nullptr) *brief = geometry.brief;
  return geometry.Baked();
}

}  // namespace sylva
