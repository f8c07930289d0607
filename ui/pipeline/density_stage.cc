// The density stage: mattes of the input views -> out/density.vdb.
#include "core/io/vdb_io.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

void AddDensityFigures(const DensitySummary& summary, const std::string& units, StageRun* run) {
  int iterations = 0;
  for (const CglsSummary& solve : summary.solves) iterations += solve.iterations;
  run->AddFigure("views", summary.num_views, "views");
  run->AddFigure("distrusted_views", summary.distrusted_views.size(), "views");
  run->AddFigure("resolution", summary.resolution, "voxels");
  run->AddFigure("voxel_size", summary.voxel_size, units);
  run->AddFigure("carved_voxels", summary.num_carved_voxels, "voxels");
  run->AddFigure("pixel_rays", summary.num_rows, "rays");
  run->AddFigure("unexplained_pixels", summary.num_unexplained_pixels, "pixels");
  run->AddFigure("iterations", iterations, "iterations");
  run->AddFigure("stored_voxels", summary.num_output_voxels, "voxels");
  run->AddFigure("solve_seconds", summary.seconds_solve, "s");
}

// The reconstruction's own steps as sub-steps.
void AddDensitySteps(const DensitySummary& summary, StageStep* step) {
  step->Add("views_and_bounds", summary.seconds_bounds)
      .Add("init", summary.seconds_init)
      .Add("system", summary.seconds_system)
      .Add("solve", summary.seconds_solve);
}

}  // namespace

StageRun RunDensityStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "density: reading mattes");
  clock.Lap("read_mattes");
  DensityOptions options = context.options.density;
  for (const View& view : views.views) {
    if (!context.project.DensityEditPath(view.name).empty() ||
        !context.project.CrownEditPath(view.name).empty()) {
      options.edited_views.push_back(view.name);
    }
  }
  DensitySummary summary;
  DensityGrid grid = ReconstructDensity(views, mattes, options, context.progress, &summary);
  AddDensitySteps(summary, &clock.Lap("reconstruct"));
  grid.SetMetadata("units", context.Units());
  run.brief = summary.BriefReport();
  AddDensityFigures(summary, context.Units(), &run);
  run.warnings = summary.warnings;
  run.outputs = {context.Out("density.vdb")};
  WriteDensityGrid(run.outputs[0], grid);
  clock.Lap("write");
  return run;
}

}  // namespace sylva
