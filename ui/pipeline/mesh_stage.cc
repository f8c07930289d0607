// The mesh stage (thesis 5.2, 5.4): skeleton with radii -> branch tubes +
// leaves -> out/tree.glb (glTF 2.0, leaves instanced) and out/tree.obj
// (+ tree.mtl), the bark alone as a closed solid in out/bark.obj (without
// separately meshed twigs: Twigs.mesh, whose tubes are in tree.*); and the
// scientific outputs: out/qsm.csv (one cylinder per skeleton edge, TreeQSM's
// columns; positions marked measured, branching a prior, radii an allometric
// prior), out/metrics.json (height, crown, DBH when metric, branches per
// order; each figure labelled measured or prior), and the skeleton for plant
// modellers: out/tree.lpy and out/tree_turtle.lpy (L-Py axioms, absolute
// @M/LineTo and relative F/+/ forms) and out/tree.mtg (OpenAlea's MTG).
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/lpy_io.h"
#include "core/io/mesh_io.h"
#include "core/io/mtg_io.h"
#include "core/io/qsm_io.h"
#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "mesh/gltf_export.h"
#include "mesh/tree_metrics.h"
#include "ui/pipeline/stage_context.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

void AddMeshFigures(const TreeGeometry& geometry, const TreeMetricsReport& metrics, StageRun* run) {
  run->AddFigure("bark_triangles", geometry.bark.NumTriangles(), "triangles");
  run->AddFigure("twig_triangles", geometry.twigs.NumTriangles(), "triangles");
  run->AddFigure("leaves", geometry.leaves.instances.size(), "leaves");
  run->AddFigure("height", metrics.height, metrics.units);
  run->AddFigure("crown_width", metrics.crown_width, metrics.units);
  run->AddFigure("tips", metrics.num_tips, "tips");
}

}  // namespace

StageRun RunMeshStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const SkeletonGraph skeleton =
      ReadSkeletonJson(context.RequireOutput("skeleton.json", "skeleton"));
  const DensityGrid density = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "mesh: reading mattes");
  ProgressTask progress(context.progress, "mesh: branches and leaves");
  progress.Update(0.0);
  const TreeGeometryOptions& geometry_options = context.options.geometry;
  LeafShape image_leaf;
  if (!geometry_options.leaf_image.empty()) {
    fs::path path(geometry_options.leaf_image);
    if (path.is_relative()) path = context.project.root() / path;
    image_leaf = LeafShapeFromImage(ReadImage(path), path.string());
  }
  clock.Lap("read");
  TreeGeometry geometry =
      BuildTreeGeometry(skeleton, density, views, mattes, context.options,
                        geometry_options.leaf_image.empty() ? nullptr : &image_leaf);
  clock.Lap("geometry").steps = std::move(geometry.profile);
  run.brief = geometry.brief;
  const TriangleMesh mesh = geometry.Baked();
  clock.Lap("bake");
  progress.Update(0.8);
  GltfExportOptions gltf;
  gltf.extras["units"] = context.Units();
  gltf.extras["branch_radii"] = "allometric prior (pipe model), not a measurement";
  const std::string units = context.Units();
  // Positions follow the photos' density; the branching is the particle
  // flow's (a prior); the radii are allometric (skeleton.radius_source).
  const SkeletonSources sources = SkeletonSources::Reconstruction();
  const TreeMetricsReport metrics =
      ComputeTreeMetrics(skeleton, &density, units, context.options.tree_metrics, sources);
  clock.Lap("metrics");
  gltf.instance_leaves = geometry_options.instance_leaves;
  run.outputs = {context.Out("tree.glb"),        context.Out("tree.obj"),
                 context.Out("bark.obj"),        context.Out("qsm.csv"),
                 context.Out("metrics.json"),    context.Out("tree.lpy"),
                 context.Out("tree_turtle.lpy"), context.Out("tree.mtg")};
  WriteGlb(run.outputs[0], geometry.Wood(), geometry.leaves, gltf);
  clock.Lap("write_glb");
  WriteObj(run.outputs[1], mesh);
  clock.Lap("write_obj");
  WriteObj(run.outputs[2], geometry.bark);
  clock.Lap("write_bark_obj");
  QsmModel qsm = QsmFromSkeleton(skeleton, units);
  qsm.position_source = sources.positions;
  qsm.branching_source = sources.branching;
  WriteQsmCsv(run.outputs[3], qsm);
  WriteTreeMetricsJson(run.outputs[4], metrics);
  WriteLpy(run.outputs[5], {skeleton}, LpyForm::kAbsolute, units);
  WriteLpy(run.outputs[6], {skeleton}, LpyForm::kTurtle, units);
  WriteMtg(run.outputs[7], {skeleton}, units);
  clock.Lap("write_skeleton_formats");
  std::ostringstream brief;
  brief << " Metrics (out/metrics.json): height " << metrics.height << " " << units
        << ", crown base " << metrics.crown_base_height << ", crown width " << metrics.crown_width
        << " (measured), " << metrics.num_tips
        << " tips (prior); cylinders in out/qsm.csv; L-Py and MTG in out/tree.lpy, "
           "tree_turtle.lpy, tree.mtg.";
  run.brief += brief.str();
  AddMeshFigures(geometry, metrics, &run);
  progress.Update(1.0);
  return run;
}

}  // namespace sylva
