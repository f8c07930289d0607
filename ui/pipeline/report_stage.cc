// The report stage: the density's projection and, once the tree exists, the
// mesh's rendered silhouette against every view's matte (input and held-out
// separately), plus the tree's metrics as the mesh stage wrote them
// (out/metrics.json) and preview pictures (leaves drawn as instances) ->
// out/report.json, report.html and pictures under out/report/.
#include "core/io/vdb_io.h"
#include "mesh/gltf_export.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

// The summary's figures: views compared and mean IoU per group (a group's
// IoU only when it has views).
void AddReportFigures(const FidelityReport& report, StageRun* run) {
  const std::pair<const char*, const FidelityGroup*> groups[] = {
      {"input", &report.input},
      {"held_out", &report.held_out},
      {"mesh_input", &report.mesh_input},
      {"mesh_held_out", &report.mesh_held_out}};
  for (const auto& [name, group] : groups) {
    run->AddFigure(std::string(name) + "_views", group->num_views, "views");
    if (group->mean_iou) run->AddFigure(std::string(name) + "_mean_iou", *group->mean_iou);
  }
}

}  // namespace

StageRun RunReportStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const DensityGrid grid = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const ImageSet image_set = context.project.LoadCameras();
  const std::vector<FloatImage> mattes = context.LoadMattes(image_set, "report: reading mattes");
  std::vector<bool> held_out;
  for (const View& view : image_set.views) held_out.push_back(context.project.IsHeldOut(view.name));
  clock.Lap("read");
  FidelityReport report =
      ComputeFidelity(grid, image_set, mattes, held_out, context.options.report);
  MarkPriorViews(context.project.prior_views(), &report);
  clock.Lap("density_fidelity");
  report.units = context.Units();
  std::error_code ec;
  if (fs::is_regular_file(context.Out("tree.glb"), ec)) {
    LeafInstances leaves;
    const TriangleMesh bark = ReadGlbKeepingLeafInstances(context.Out("tree.glb"), &leaves);
    TriangleMesh mesh = bark;
    mesh.Append(leaves.Bake());
    clock.Lap("read_tree");
    AddMeshFidelity(mesh, image_set, context.options.report, &report);
    clock.Lap("mesh_fidelity");
    // The tree's figures are the mesh stage's: one definition of each.
    report.metrics = ReadTreeMetricsJson(context.RequireOutput("metrics.json", "mesh"));
    report.has_metrics = true;
    ProgressTask progress(context.progress, "report: preview pictures");
    progress.Update(0.0);
    report.previews = RenderReportPreviews(bark, &leaves, context.options.report);
    progress.Update(1.0);
    clock.Lap("previews");
  }
  std::map<std::string, std::string> briefs;
  for (const char* stage : {"density", "skeleton", "mesh"}) {
    const std::string brief = context.RecordedBrief(stage);
    if (!brief.empty()) briefs[stage] = brief;
  }
  run.warnings = FidelityWarnings(report, context.options.report);
  AddWarnings(run.warnings, &report);
  for (const char* stage : {"matte", "register", "density", "attract", "skeleton", "mesh"}) {
    AddWarnings(context.RecordedWarnings(stage), &report);
    std::vector<StageFigure> figures = context.RecordedFigures(stage);
    if (!figures.empty()) report.stage_figures.emplace_back(stage, std::move(figures));
  }
  run.brief = report.BriefReport();
  AddReportFigures(report, &run);
  run.outputs =
      WriteFidelityReport(report, briefs, context.options.report, context.project.OutDir());
  clock.Lap("write");
  return run;
}

}  // namespace sylva
