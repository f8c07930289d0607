// The mesh stage (thesis 5.2, 5.4): skeleton with radii -> branch tubes +
// leaves -> out/tree.glb (glTF 2.0) and out/tree.obj (+ tree.mtl).
#include <sstream>

#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/util/random.h"
#include "mesh/branch_mesh.h"
#include "mesh/gltf_export.h"
#include "mesh/leaves.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

constexpr uint64_t kLeafSeedStream = 2;

}  // namespace

StageRun RunMeshStage(const StageContext& context) {
  const PipelineOptions& options = context.options;
  const SkeletonGraph skeleton = ReadSkeletonJson(context.RequireOutput("skeleton.json", "skeleton"));
  const DensityGrid density = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  ProgressTask progress(context.progress, "mesh: branches");
  progress.Update(0.0);
  BranchMeshSummary branch_summary;
  TriangleMesh mesh = MeshBranches(skeleton, options.branch_mesh, &branch_summary);
  progress.Update(0.3);

  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "mesh: reading mattes");
  LeafOptions leaf_options = options.leaves;
  leaf_options.seed = DeriveSeed(options.general.seed, kLeafSeedStream);
  LeafSummary leaf_summary;
  mesh.Append(GenerateLeaves(skeleton, density, views, mattes, leaf_options, &leaf_summary));
  ProgressTask writing(context.progress, "mesh: writing");
  writing.Update(0.0);

  GltfExportOptions gltf;
  gltf.extras["units"] = context.project.units();
  gltf.extras["branch_radii"] = "allometric prior (pipe model), not a measurement";
  StageRun run;
  run.brief = branch_summary.BriefReport() + " " + leaf_summary.BriefReport();
  run.outputs = {context.Out("tree.glb"), context.Out("tree.obj")};
  WriteGlb(run.outputs[0], mesh, gltf);
  WriteObj(run.outputs[1], mesh);
  writing.Update(1.0);
  return run;
}

}  // namespace sylva
