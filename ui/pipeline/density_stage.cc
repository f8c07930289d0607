// The density stage: mattes of the input views -> out/density.vdb.
#include "core/io/vdb_io.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {

StageRun RunDensityStage(const StageContext& context) {
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "density: reading mattes");
  DensitySummary summary;
  DensityGrid grid =
      ReconstructDensity(views, mattes, context.options.density, context.progress, &summary);
  grid.SetMetadata("units", context.Units());
  StageRun run;
  run.brief = summary.BriefReport();
  run.warnings = summary.warnings;
  run.outputs = {context.Out("density.vdb")};
  WriteDensityGrid(run.outputs[0], grid);
  return run;
}

}  // namespace sylva
