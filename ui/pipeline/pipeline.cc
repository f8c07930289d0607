#include "ui/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <optional>
#include <sstream>
#include <thread>

#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

// The report's density projections depend on the density alone, so they
// are made on a thread of their own while the stages between the density
// and the report run (those keep about 1.3 of 2 cores busy): on the demo,
// the report's 0.14 s of projections overlap them, which run 0.02-0.05 s
// slower for it. Any error is left to the report
// stage, which then makes them itself. The thread is joined by Wait, or on
// destruction when another stage's error leaves Run first.
class ProjectionsBeside {
 public:
  ProjectionsBeside() = default;
  ProjectionsBeside(const ProjectionsBeside&) = delete;
  ProjectionsBeside& operator=(const ProjectionsBeside&) = delete;
  ~ProjectionsBeside() { Join(); }

  // `context` refers to the pipeline's project and options, which outlive
  // this object.
  void Start(StageContext context) {
    Join();
    made_.reset();
    thread_ = std::thread([this, context] {
      try {
        made_ = MakeReportProjections(context);
      } catch (...) {
        made_.reset();
      }
    });
  }

  // The projections once made, or null (never started, or failed).
  const ReportProjections* Wait() {
    Join();
    return made_.has_value() ? &*made_ : nullptr;
  }

 private:
  void Join() {
    if (thread_.joinable()) thread_.join();
  }

  std::thread thread_;
  std::optional<ReportProjections> made_;  // read only after the join
};

constexpr char kSylvaVersion[] = "0.3.0";

// What a stage is and what it depends on.
struct StageDefinition {
  StageInfo info;
  // Bump when the stage's algorithm changes its outputs, so old results are
  // recomputed.
  const char* version;
  // Option sections (Section.field prefixes) and single keys it reads.
  std::vector<std::string> options;
  std::vector<Stage> upstream;
  bool reads_held_out_mattes;
  StageRun (*run)(const StageContext&);
  // Whether the project needs the stage (the matte stage only when mattes
  // are computed); a stage that does not apply is skipped, not stale.
  bool (*applies)(const Project&);
};

bool Always(const Project&) { return true; }
bool WhenComputingMattes(const Project& project) { return project.ComputesMattes(); }

const std::vector<StageDefinition>& Definitions() {
  static const std::vector<StageDefinition> definitions = {
      {{Stage::kMatte, "matte",
        "alpha mattes from the photos: automatic trimap refined by alpha matting, painted "
        "trimaps in edits/trimaps/ override it (out/mattes/)"},
       "matte/2",
       {"Matting.", "MatteSet."},
       {},
       true,
       RunMatteStage,
       WhenComputingMattes},
      {{Stage::kRegister, "register",
        "cameras of the photos (given, COLMAP, or loose azimuths refined with Ceres) in "
        "sylva's world frame: up +Z, tree base at the origin (out/cameras/)"},
       "register/2",
       {"Colmap.", "WorldFrame.", "LooseCameras."},
       {Stage::kMatte},
       true,
       RunRegisterStage,
       Always},
      {{Stage::kDensity, "density",
        "back-project the mattes into a voxel density grid (out/density.vdb)"},
       "density/3",
       {"Density."},
       {Stage::kRegister},
       false,
       RunDensityStage,
       Always},
      {{Stage::kAttract, "attract",
        "attractor graphs per photo: edited graphs or drawn strokes in edits/, else traced by "
        "livewire to the tree base (out/attractors/)"},
       "attract/1",
       {"Attractors.", "TreeBase.", "Skeleton.base", "General.seed"},
       {Stage::kDensity},
       false,
       RunAttractStage,
       Always},
      {{Stage::kSkeleton, "skeleton",
        "particle flow from the density to the tree base, steered by the attractor graphs' "
        "direction fields; skeleton with pipe-model radii, scaled to the mattes on leafless plants "
        "(out/skeleton.json, skeleton.ply)"},
       "skeleton/6",
       {"TreeBase.", "DirectionField.", "ParticleFlow.", "Skeleton.", "Allometry.", "BranchWidth.",
        "Leaves.num_leaves", "General.seed"},
       {Stage::kDensity, Stage::kAttract},
       false,
       RunSkeletonStage,
       Always},
      {{Stage::kMesh, "mesh", "branch tubes and leaves from the skeleton (out/tree.glb, tree.obj)"},
       "mesh/5",
       {"BranchMesh.", "Twigs.", "Leaves.", "Export.", "TreeMetrics.", "General.seed"},
       {Stage::kDensity, Stage::kSkeleton},
       false,
       RunMeshStage,
       Always},
      {{Stage::kReport, "report",
        "per-view fidelity of the density and the mesh against the mattes, tree metrics "
        "(out/report.json, report.html)"},
       "report/6",
       {"Report."},
       {Stage::kDensity, Stage::kSkeleton, Stage::kMesh},
       true,
       RunReportStage,
       Always},
  };
  return definitions;
}

const StageDefinition& Definition(Stage stage) {
  for (const StageDefinition& definition : Definitions()) {
    if (definition.info.stage == stage) return definition;
  }
  SYLVA_CHECK(false) << "unknown stage";
  return Definitions().front();
}

// [{"name", "seconds", "steps": [...]}, ...] (steps only where there are some).
Json ProfileJson(const std::vector<StageStep>& steps) {
  Json json = Json::array();
  for (const StageStep& step : steps) {
    Json entry = {{"name", step.name}, {"seconds", step.seconds}};
    if (!step.steps.empty()) entry["steps"] = ProfileJson(step.steps);
    json.push_back(entry);
  }
  return json;
}

// The run's profile for out/run.json: every stage of the run, its wall time
// (0 for one that was up to date) and its steps.
Json RunProfileJson(const RunSummary& summary) {
  Json stages = Json::array();
  double total = 0.0;
  for (const StageRun& run : summary.stages) {
    total += run.up_to_date ? 0.0 : run.seconds;
    stages.push_back({{"stage", GetStageInfo(run.stage).name},
                      {"up_to_date", run.up_to_date},
                      {"seconds", run.up_to_date ? 0.0 : run.seconds},
                      {"steps", run.up_to_date ? Json::array() : ProfileJson(run.profile)}});
  }
  return {{"seconds", total}, {"stages", stages}};
}

std::string LocalTime() {
  const std::time_t now = std::time(nullptr);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%S%z", std::localtime(&now));
  return buffer;
}

}  // namespace

std::vector<StageInfo> AllStages() {
  std::vector<StageInfo> stages;
  for (const StageDefinition& definition : Definitions()) stages.push_back(definition.info);
  return stages;
}

StageInfo GetStageInfo(Stage stage) { return Definition(stage).info; }

Stage ParseStage(const std::string& name, const std::string& source) {
  std::string names;
  for (const StageDefinition& definition : Definitions()) {
    if (name == definition.info.name) return definition.info.stage;
    names += (names.empty() ? "" : ", ") + std::string(definition.info.name);
  }
  SYLVA_INPUT_ERROR(source) << "unknown stage '" << name << "' (stages: " << names << ")";
  return Stage::kDensity;
}

std::string RunSummary::BriefReport() const {
  std::ostringstream out;
  for (const StageRun& run : stages) {
    out << GetStageInfo(run.stage).name << ": "
        << (run.up_to_date ? "up to date (inputs unchanged)" : run.brief) << "\n";
    if (!run.figures.empty()) out << "  figures: " << FiguresText(run.figures) << "\n";
    if (!run.up_to_date && !run.profile.empty()) {
      out << "  time: " << ProfileText(run.profile) << "\n";
    }
    for (const Warning& warning : run.warnings) out << "  warning " << warning.ToString() << "\n";
  }
  return out.str();
}

Pipeline::Pipeline(const Project& project, const PipelineOptions& options,
                   ProgressReporter* progress)
    : project_(project), options_(options), progress_(progress) {
  options_.Check();
}

StageInputs Pipeline::Inputs(Stage stage) const {
  const StageDefinition& definition = Definition(stage);
  StageInputs inputs;
  inputs.version = definition.version;
  inputs.options = definition.options;
  inputs.upstream = definition.upstream;
  auto& files = inputs.files;
  const auto in_project = [&](const std::string& path) {
    return fs::path(path).is_absolute() ? fs::path(path) : project_.root() / path;
  };
  if (stage == Stage::kMatte || stage == Stage::kRegister) {
    // These stages read the photos (and the register stage the mattes and
    // the camera source) by name, before any cameras exist.
    if (stage == Stage::kRegister) {
      for (const fs::path& file : project_.CameraSourceFiles()) files.emplace_back("cameras", file);
    }
    const std::string& background = options_.matte_stage.background_photo;
    if (stage == Stage::kMatte && !background.empty()) {
      files.emplace_back("background photo", in_project(background));
    }
    for (const std::string& name : project_.photo_names()) {
      files.emplace_back("photo", project_.PhotoPath(name));
      if (stage == Stage::kMatte) {
        const fs::path hint = project_.TrimapHintPath(name);
        if (!hint.empty()) files.emplace_back("trimap", hint);
      } else {
        files.emplace_back("matte", project_.MattePath(name));
      }
    }
  } else {
    for (const fs::path& file : project_.CameraFiles()) files.emplace_back("cameras", file);
    const ImageSet image_set = project_.LoadCameras();
    for (const View& view : image_set.views) {
      const bool held_out = project_.IsHeldOut(view.name);
      if (held_out && !definition.reads_held_out_mattes) continue;
      files.emplace_back(held_out ? "held-out matte" : "matte", project_.MattePath(view.name));
      if (!held_out) {
        files.emplace_back("density edit", project_.DensityEditPath(view.name));
        files.emplace_back("crown outline", project_.CrownEditPath(view.name));
      }
      if (stage == Stage::kAttract && !held_out) {
        // The attract stage also reads the photos and what a person drew.
        files.emplace_back("photo", project_.PhotoPath(view.name));
        files.emplace_back("attractor edit", project_.AttractorEditPath(view.name));
        files.emplace_back("strokes", project_.StrokesPath(view.name));
      }
    }
  }
  if (stage == Stage::kMesh && !options_.geometry.leaf_image.empty()) {
    files.emplace_back("leaf image", in_project(options_.geometry.leaf_image));
  }
  // Optional inputs not there (no strokes drawn) have no path: drawing one
  // adds it to the list.
  files.erase(std::remove_if(files.begin(), files.end(),
                             [](const auto& file) { return file.second.empty(); }),
              files.end());
  return inputs;
}

std::string Pipeline::StageKey(Stage stage) const {
  if (!Definition(stage).applies(project_)) return "not needed";
  const StageInputs inputs = Inputs(stage);
  std::string text = inputs.version + ";";
  for (const auto& [what, file] : inputs.files) text += what + " " + FileKey(project_, file) + ";";
  text += OptionsText(options_, inputs.options);
  for (Stage upstream : inputs.upstream) {
    text += std::string(GetStageInfo(upstream).name) + "=" + StageKey(upstream) + ";";
  }
  return HexString(Fnv1a64(text));
}

bool Pipeline::IsUpToDate(Stage stage) const {
  const Json records = ParseJson(ReadStageRecordsText(project_), "stage records");
  const std::string name = GetStageInfo(stage).name;
  if (!records.contains(name)) return false;
  const Json& record = records[name];
  if (!record.contains("key") || record["key"] != StageKey(stage)) return false;
  std::error_code ec;
  for (const auto& output : record.value("outputs", Json::array())) {
    if (!output.is_string() ||
        !fs::is_regular_file(project_.root() / output.get<std::string>(), ec)) {
      return false;
    }
  }
  return true;
}

void Pipeline::Record(const StageRun& run) const {
  Json records = ParseJson(ReadStageRecordsText(project_), "stage records");
  Json outputs = Json::array();
  for (const fs::path& output : run.outputs) {
    outputs.push_back(fs::relative(output, project_.root()).generic_string());
  }
  Json warnings = Json::array();
  for (const Warning& warning : run.warnings) {
    warnings.push_back(
        {{"code", warning.code}, {"message", warning.message}, {"subject", warning.subject}});
  }
  Json figures = Json::array();
  for (const StageFigure& figure : run.figures) {
    figures.push_back({{"key", figure.key}, {"value", figure.value}, {"unit", figure.unit}});
  }
  records[GetStageInfo(run.stage).name] = {{"key", StageKey(run.stage)},
                                           {"outputs", outputs},
                                           {"seconds", run.seconds},
                                           {"summary", run.brief},
                                           {"figures", figures},
                                           {"warnings", warnings},
                                           {"profile", ProfileJson(run.profile)},
                                           {"finished", LocalTime()}};
  WriteJsonFile(project_.CacheDir() / "stages.json", records);
}

void Pipeline::WriteRunRecord(const RunSummary& summary) const {
  PipelineOptions copy = options_;
  OptionRegistry registry;
  RegisterPipelineOptions(&copy, &registry);
  const Json record = {{"sylva_version", kSylvaVersion},
                       {"finished", LocalTime()},
                       {"units", StageContext{project_, options_, progress_, false}.Units()},
                       {"held_out", project_.held_out()},
                       {"profile", RunProfileJson(summary)},
                       {"options", registry.ToJson(/*only_changed=*/false)}};
  WriteJsonFile(project_.OutDir() / "run.json", record);
}

RunSummary Pipeline::Run(Stage until, bool force) {
  std::vector<Stage> to_run;
  for (const StageDefinition& definition : Definitions()) {
    const Stage stage = definition.info.stage;
    if (definition.applies(project_)) {
      // A stage re-runs when a stage it builds on re-runs, or when it is out
      // of date (its key is only computed when its upstream stages are up
      // to date: before registration there are no cameras to key on).
      bool stale = force;
      for (Stage upstream : definition.upstream) {
        stale = stale || std::find(to_run.begin(), to_run.end(), upstream) != to_run.end();
      }
      stale = stale || !IsUpToDate(stage);
      if (stale) to_run.push_back(stage);
    }
    if (stage == until) break;
  }
  // A bad held-out matte must fail the run before any stage writes: only
  // the report reads them, after the others have written.
  if (!to_run.empty() && to_run.back() == Stage::kReport && to_run.size() > 1) {
    CheckHeldOutMattes();
  }
  const auto runs = [&](Stage stage) {
    return std::find(to_run.begin(), to_run.end(), stage) != to_run.end();
  };
  // Worth it when a stage runs between the density and the report.
  const bool project_beside =
      runs(Stage::kDensity) && runs(Stage::kReport) &&
      (runs(Stage::kAttract) || runs(Stage::kSkeleton) || runs(Stage::kMesh));
  ProjectionsBeside projections;
  RunSummary summary;
  for (const StageDefinition& definition : Definitions()) {
    const Stage stage = definition.info.stage;
    if (runs(stage)) {
      summary.stages.push_back(
          Execute(stage, force, stage == Stage::kReport ? projections.Wait() : nullptr));
      if (stage == Stage::kDensity && project_beside) {
        projections.Start(StageContext{project_, options_, nullptr, force});
      }
    } else if (definition.applies(project_)) {
      StageRun skipped;
      skipped.stage = stage;
      skipped.up_to_date = true;
      skipped.warnings = ReadRecordedWarnings(project_, definition.info.name);
      skipped.figures = ReadRecordedFigures(project_, definition.info.name);
      summary.stages.push_back(skipped);
    }
    if (stage == until) break;
  }
  WriteRunRecord(summary);
  return summary;
}

void Pipeline::CheckHeldOutMattes() const {
  if (project_.ComputesMattes()) return;  // the matte stage makes them
  ProgressTask progress(progress_, "checking held-out mattes");
  const std::vector<std::string>& held_out = project_.held_out();
  for (size_t i = 0; i < held_out.size(); ++i) {
    const ImageHeader header = ReadImageHeader(project_.PhotoPath(held_out[i]));
    project_.LoadMatte(held_out[i], header.width, header.height);
    progress.Update(static_cast<double>(i + 1) / held_out.size());
  }
}

StageRun Pipeline::RunStage(Stage stage) {
  if (!Definition(stage).applies(project_)) {
    StageRun run;
    run.stage = stage;
    run.brief = "not needed (the project's mattes are given, not computed)";
    return run;
  }
  StageRun run = Execute(stage);
  RunSummary summary;
  summary.stages.push_back(run);
  WriteRunRecord(summary);
  return run;
}

StageRun Pipeline::Execute(Stage stage, bool cold, const ReportProjections* report_projections) {
  if (on_stage_start_) on_stage_start_(stage);
  const auto start = std::chrono::steady_clock::now();
  const StageContext context{project_, options_, progress_, cold, report_projections};
  StageRun run = Definition(stage).run(context);
  run.stage = stage;
  run.seconds = SecondsSince(start);
  run.AddFigure("seconds", run.seconds, "s");
  Record(run);
  return run;
}

}  // namespace sylva
