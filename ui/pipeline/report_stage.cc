// The report stage: the density's projection and, once the tree exists, the
// mesh's rendered silhouette against every view's matte (input and held-out
// separately), plus the tree's metrics as the mesh stage wrote them
// (out/metrics.json) and preview pictures (leaves drawn as instances) ->
// out/report.json, report.html and pictures under out/report/.
#include <cstring>

#include "core/io/vdb_io.h"
#include "core/util/file_util.h"
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

// cache/report_projections.bin: the density's projection into every view,
// the report's slowest density figure, kept so that a run in which the
// density did not change (a stroke edit, a new mesh option) reuses it.
// Binary: the magic line, the key line, the count n (uint64), then per view
// width and height (int32) and its floats, in this machine's byte order. A
// missing, old or damaged file only means projecting again.
constexpr char kProjectionsMagic[] = "sylva-report-projections/1\n";

fs::path ProjectionsPath(const StageContext& context) {
  return context.project.CacheDir() / "report_projections.bin";
}

// What the projections depend on: the density file, the cameras, the
// views and the Report options.
std::string ProjectionsKey(const StageContext& context, const ImageSet& image_set) {
  std::string key = OptionsText(context.options, {"Report."});
  key += ";" + FileKey(context.project, context.Out("density.vdb"));
  for (const fs::path& file : context.project.CameraFiles()) {
    key += ";" + FileKey(context.project, file);
  }
  for (const View& view : image_set.views) key += ";" + view.name;
  return HexString(Fnv1a64(key));
}

std::vector<FloatImage> ReadProjections(const fs::path& path, const std::string& key) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return {};
  const std::string bytes = ReadFileToString(path);
  const std::string head = kProjectionsMagic + key + "\n";
  if (bytes.compare(0, head.size(), head) != 0) return {};
  size_t at = head.size();
  uint64_t n = 0;
  if (bytes.size() < at + sizeof(n)) return {};
  std::memcpy(&n, bytes.data() + at, sizeof(n));
  at += sizeof(n);
  std::vector<FloatImage> projections;
  for (uint64_t k = 0; k < n; ++k) {
    int32_t size[2];
    if (bytes.size() - at < sizeof(size)) return {};
    std::memcpy(size, bytes.data() + at, sizeof(size));
    at += sizeof(size);
    if (size[0] <= 0 || size[1] <= 0 ||
        (bytes.size() - at) / sizeof(float) / size[0] < static_cast<uint64_t>(size[1])) {
      return {};
    }
    FloatImage image(size[0], size[1], 1);
    std::memcpy(image.data(), bytes.data() + at, image.values().size() * sizeof(float));
    at += image.values().size() * sizeof(float);
    projections.push_back(std::move(image));
  }
  if (at != bytes.size()) return {};
  return projections;
}

void WriteProjections(const fs::path& path, const std::string& key,
                      const std::vector<FloatImage>& projections) {
  std::string bytes = kProjectionsMagic + key + "\n";
  const uint64_t n = projections.size();
  bytes.append(reinterpret_cast<const char*>(&n), sizeof(n));
  for (const FloatImage& image : projections) {
    const int32_t size[2] = {image.width(), image.height()};
    bytes.append(reinterpret_cast<const char*>(size), sizeof(size));
    bytes.append(reinterpret_cast<const char*>(image.data()),
                 image.values().size() * sizeof(float));
  }
  fs::create_directories(path.parent_path());
  AtomicWriteString(path, bytes);
}

std::vector<bool> HeldOutViews(const StageContext& context, const ImageSet& image_set) {
  std::vector<bool> held_out;
  for (const View& view : image_set.views) held_out.push_back(context.project.IsHeldOut(view.name));
  return held_out;
}

}  // namespace

ReportProjections MakeReportProjections(const StageContext& context) {
  const DensityGrid grid = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const ImageSet image_set = context.project.LoadCameras();
  const std::vector<FloatImage> mattes = context.LoadMattes(image_set, "report: reading mattes");
  ReportProjections made;
  made.key = ProjectionsKey(context, image_set);
  ComputeFidelity(grid, image_set, mattes, HeldOutViews(context, image_set), context.options.report,
                  &made.images);
  return made;
}

StageRun RunReportStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const DensityGrid grid = ReadDensityGrid(context.RequireOutput("density.vdb", "density"));
  const ImageSet image_set = context.project.LoadCameras();
  const std::vector<FloatImage> mattes = context.LoadMattes(image_set, "report: reading mattes");
  const std::vector<bool> held_out = HeldOutViews(context, image_set);
  clock.Lap("read");
  // The projections made in this run beside the stages before (the same
  // ones this stage would make), else those of an earlier run with the
  // same density (cache/report_projections.bin), else made here.
  const std::string projections_key = ProjectionsKey(context, image_set);
  const int num_views = image_set.NumViews();
  std::vector<FloatImage> projections;
  const ReportProjections* made = context.report_projections;
  const bool made_before = made != nullptr && made->key == projections_key &&
                           static_cast<int>(made->images.size()) == num_views;
  if (made_before) {
    projections = made->images;
  } else if (!context.cold) {
    projections = ReadProjections(ProjectionsPath(context), projections_key);
  }
  const bool reused = !made_before && static_cast<int>(projections.size()) == num_views;
  FidelityReport report =
      ComputeFidelity(grid, image_set, mattes, held_out, context.options.report, &projections);
  if (!reused) WriteProjections(ProjectionsPath(context), projections_key, projections);
  run.AddFigure("reused_projections", reused ? num_views : 0, "views");
  run.AddFigure("projections_made_before", made_before ? num_views : 0, "views");
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
