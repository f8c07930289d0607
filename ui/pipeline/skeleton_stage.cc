// The skeleton stage (thesis 3.4, 3.5 and 5.1): out/density.vdb -> particle
// flow to the tree base, steered by the direction field of the attract
// stage's graphs (out/attractors/) -> skeleton with pipe-model radii scaled to the trunk
// width seen in the mattes. Writes out/skeleton.json, out/skeleton.ply
// (AdTree layout) and out/skeleton_raw.json (traces before simplification).
// Thin wood that carries density painted in (edits/density/) is kept.
#include <tbb/parallel_invoke.h>

#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/util/threading.h"
#include "ui/pipeline/stage_context.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {

StageRun RunSkeletonStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const ImageSet views = context.InputViews();
  // The inputs are read side by side.
  DensityGrid density;
  std::vector<FloatImage> mattes;
  std::vector<AttractorGraph2D> attractors;
  std::vector<FloatImage> painted_in(views.NumViews());
  tbb::parallel_invoke(
      [&] { density = ReadDensityGrid(context.RequireOutput("density.vdb", "density")); },
      [&] { mattes = context.LoadMattes(views, "skeleton: reading mattes"); },
      [&] {
        attractors = LoadAttractorGraphs(context.project, views);
        ParallelForFirstError(views.NumViews(), [&](int v) {
          painted_in[v] = context.project.LoadPaintedIn(views, v);
        });
      });
  clock.Lap("read");
  BuiltSkeleton built = BuildSkeleton(density, views, mattes, attractors, context.options,
                                      context.progress, &painted_in);
  clock.Lap("build").steps = std::move(built.profile);
  const std::string units = context.Units();
  run.brief = built.brief;
  run.AddFigure("nodes", built.skeleton.NumNodes(), "nodes");
  run.AddFigure("tips", built.skeleton.Tips().size(), "tips");
  run.AddFigure("raw_nodes", built.raw.NumNodes(), "nodes");
  run.AddFigure("trunk_radius", built.trunk_radius, units);
  run.outputs = {context.Out("skeleton.json"), context.Out("skeleton.ply"),
                 context.Out("skeleton_raw.json")};
  tbb::parallel_invoke([&] { WriteSkeletonJson(run.outputs[0], built.skeleton, units); },
                       [&] { WriteSkeletonPly(run.outputs[1], built.skeleton, units); },
                       [&] { WriteSkeletonJson(run.outputs[2], built.raw, units); });
  clock.Lap("write");
  return run;
}

}  // namespace sylva
