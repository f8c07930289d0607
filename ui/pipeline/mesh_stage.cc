// The mesh stage (thesis 5.2, 5.4): skeleton with radii -> branch tubes +
// leaves -> out/tree.glb (glTF 2.0) and out/tree.obj (+ tree.mtl).
#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "mesh/gltf_export.h"
#include "ui/pipeline/stage_context.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {

StageRun RunMeshStage(const StageContext& context) {
  const SkeletonGraph skeleton =
      ReadSkeletonJson(context.RequireOutput("skeleton.json", "skeleton"));
  const DensityGrid density = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "mesh: reading mattes");
  ProgressTask progress(context.progress, "mesh: branches and leaves");
  progress.Update(0.0);
  StageRun run;
  const TriangleMesh mesh =
      BuildTreeMesh(skeleton, density, views, mattes, context.options, &run.brief);
  progress.Update(0.8);
  GltfExportOptions gltf;
  gltf.extras["units"] = context.Units();
  gltf.extras["branch_radii"] = "allometric prior (pipe model), not a measurement";
  run.outputs = {context.Out("tree.glb"), context.Out("tree.obj")};
  WriteGlb(run.outputs[0], mesh, gltf);
  WriteObj(run.outputs[1], mesh);
  progress.Update(1.0);
  return run;
}

}  // namespace sylva
