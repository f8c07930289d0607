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
#include <tbb/parallel_invoke.h>

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

// Writes the mesh stage's outputs (their paths in `outputs`, in this order)
// and returns the tree's metrics. Three independent, mostly serial groups
// run side by side (each file is written by one of them; `steps` gets their
// times, which overlap): the baked mesh's OBJ; the glTF and the bark's OBJ;
// the metrics with the skeleton's formats.
TreeMetricsReport WriteMeshOutputs(const StageContext& context, const SkeletonGraph& skeleton,
                                   const DensityGrid& density, const TreeGeometry& geometry,
                                   std::vector<fs::path>* outputs, std::vector<StageStep>* steps) {
  const std::string units = context.Units();
  GltfExportOptions gltf;
  gltf.extras["units"] = units;
  gltf.extras["branch_radii"] = "allometric prior (pipe model), not a measurement";
  gltf.instance_leaves = context.options.geometry.instance_leaves;
  // Positions follow the photos' density; the branching is the particle
  // flow's (a prior); the radii are allometric (skeleton.radius_source).
  const SkeletonSources sources = SkeletonSources::Reconstruction();
  *outputs = {context.Out("tree.glb"),        context.Out("tree.obj"),     context.Out("bark.obj"),
              context.Out("qsm.csv"),         context.Out("metrics.json"), context.Out("tree.lpy"),
              context.Out("tree_turtle.lpy"), context.Out("tree.mtg")};
  const std::vector<fs::path>& out = *outputs;
  TreeMetricsReport metrics;
  double seconds[3] = {};
  const auto timed = [&seconds](int k, const auto& work) {
    return [&seconds, k, &work] { seconds[k] = TimeOf(work); };
  };
  const auto baked_obj = [&] { WriteObj(out[1], geometry.Baked()); };
  const auto glb_and_bark = [&] {
    WriteGlb(out[0], geometry.Wood(), geometry.leaves, gltf);
    WriteObj(out[2], geometry.bark);
  };
  const auto metrics_and_skeleton = [&] {
    metrics = ComputeTreeMetrics(skeleton, &density, units, context.options.tree_metrics, sources);
    QsmModel qsm = QsmFromSkeleton(skeleton, units);
    qsm.position_source = sources.positions;
    qsm.branching_source = sources.branching;
    WriteQsmCsv(out[3], qsm);
    WriteTreeMetricsJson(out[4], metrics);
    WriteLpy(out[5], {skeleton}, LpyForm::kAbsolute, units);
    WriteLpy(out[6], {skeleton}, LpyForm::kTurtle, units);
    WriteMtg(out[7], {skeleton}, units);
  };
  tbb::parallel_invoke(timed(0, baked_obj), timed(1, glb_and_bark), timed(2, metrics_and_skeleton));
  steps->push_back({"tree_obj", seconds[0], {}});
  steps->push_back({"glb_and_bark_obj", seconds[1], {}});
  steps->push_back({"metrics_and_skeleton_formats", seconds[2], {}});
  return metrics;
}

}  // namespace

StageRun RunMeshStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const ImageSet views = context.InputViews();
  // The inputs are read side by side.
  SkeletonGraph skeleton;
  DensityGrid density;
  std::vector<FloatImage> mattes;
  tbb::parallel_invoke(
      [&] { skeleton = ReadSkeletonJson(context.RequireOutput("skeleton.json", "skeleton")); },
      [&] { density = ReadDensityGrid(context.RequireOutput("density.vdb", "density")); },
      [&] { mattes = context.LoadMattes(views, "mesh: reading mattes"); });
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
  progress.Update(0.8);
  std::vector<StageStep> output_steps;
  const TreeMetricsReport metrics =
      WriteMeshOutputs(context, skeleton, density, geometry, &run.outputs, &output_steps);
  clock.Lap("outputs").steps = std::move(output_steps);
  std::ostringstream brief;
  brief << " Metrics (out/metrics.json): height " << metrics.height << " " << metrics.units
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
