#include "ui/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr char kSylvaVersion[] = "0.2.0";

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
};

const std::vector<StageDefinition>& Definitions() {
  static const std::vector<StageDefinition> definitions = {
      {{Stage::kDensity, "density",
        "back-project the mattes into a voxel density grid (out/density.vdb)"},
       "density/1", {"Density."}, {}, false, RunDensityStage},
      {{Stage::kSkeleton, "skeleton",
        "particle flow from the density to the tree base; skeleton with allometric radii "
        "(out/skeleton.json, skeleton.ply)"},
       "skeleton/1", {"TreeBase.", "ParticleFlow.", "Skeleton.", "Allometry.", "General.seed"},
       {Stage::kDensity}, false, RunSkeletonStage},
      {{Stage::kMesh, "mesh",
        "branch tubes and leaves from the skeleton (out/tree.glb, tree.obj)"},
       "mesh/1", {"BranchMesh.", "Leaves.", "General.seed"}, {Stage::kDensity, Stage::kSkeleton},
       false, RunMeshStage},
      {{Stage::kReport, "report",
        "per-view fidelity of the density and the mesh against the mattes, tree metrics "
        "(out/report.json, report.html)"},
       "report/2", {"Report."}, {Stage::kDensity, Stage::kSkeleton, Stage::kMesh}, true,
       RunReportStage},
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

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The values of the options a stage reads, as canonical text.
std::string OptionsText(const PipelineOptions& options, const std::vector<std::string>& prefixes) {
  PipelineOptions copy = options;
  OptionRegistry registry;
  RegisterPipelineOptions(&copy, &registry);
  std::string text;
  for (const auto& entry : registry.entries()) {
    for (const std::string& prefix : prefixes) {
      if (entry.key.rfind(prefix, 0) == 0) text += entry.key + "=" + entry.get() + ";";
    }
  }
  return text;
}

// A file's identity in a stage key: its path (relative to the project for
// files inside it, so a moved project stays up to date) and its stamp.
std::string FileKey(const Project& project, const fs::path& file) {
  const fs::path relative = file.lexically_relative(project.root());
  const bool inside = !relative.empty() && *relative.begin() != "..";
  return (inside ? relative : file).generic_string() + ":" + HexString(FileStamp(file));
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
  }
  return out.str();
}

Pipeline::Pipeline(const Project& project, const PipelineOptions& options,
                   ProgressReporter* progress)
    : project_(project), options_(options), progress_(progress) {
  options_.Check();
}

std::string Pipeline::StageKey(Stage stage) const {
  const StageDefinition& definition = Definition(stage);
  std::string text = std::string(definition.version) + ";";
  for (const fs::path& file : project_.CameraFiles()) text += FileKey(project_, file) + ";";
  const ImageSet image_set = project_.LoadCameras();
  for (const View& view : image_set.views) {
    const bool held_out = project_.IsHeldOut(view.name);
    if (held_out && !definition.reads_held_out_mattes) continue;
    text += view.name + (held_out ? "(held out)" : "") + "=" +
            FileKey(project_, project_.MattePath(view.name)) + ";";
  }
  text += OptionsText(options_, definition.options);
  for (Stage upstream : definition.upstream) {
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
  records[GetStageInfo(run.stage).name] = {{"key", StageKey(run.stage)},
                                           {"outputs", outputs},
                                           {"seconds", run.seconds},
                                           {"summary", run.brief},
                                           {"finished", LocalTime()}};
  WriteJsonFile(project_.CacheDir() / "stages.json", records);
}

void Pipeline::WriteRunRecord() const {
  PipelineOptions copy = options_;
  OptionRegistry registry;
  RegisterPipelineOptions(&copy, &registry);
  const Json record = {{"sylva_version", kSylvaVersion},
                       {"finished", LocalTime()},
                       {"units", project_.units()},
                       {"held_out", project_.held_out()},
                       {"options", registry.ToJson(/*only_changed=*/false)}};
  WriteJsonFile(project_.OutDir() / "run.json", record);
}

RunSummary Pipeline::Run(Stage until, bool force) {
  std::vector<Stage> to_run;
  for (const StageDefinition& definition : Definitions()) {
    const Stage stage = definition.info.stage;
    // A stage re-runs when it is out of date or a stage it builds on re-runs.
    bool stale = force || !IsUpToDate(stage);
    for (Stage upstream : definition.upstream) {
      stale = stale || std::find(to_run.begin(), to_run.end(), upstream) != to_run.end();
    }
    if (stale) to_run.push_back(stage);
    if (stage == until) break;
  }
  // A bad held-out matte must fail the run before any stage writes: only
  // the report reads them, after the others have written.
  if (!to_run.empty() && to_run.back() == Stage::kReport && to_run.size() > 1) {
    CheckHeldOutMattes();
  }
  RunSummary summary;
  for (const StageDefinition& definition : Definitions()) {
    const Stage stage = definition.info.stage;
    if (std::find(to_run.begin(), to_run.end(), stage) != to_run.end()) {
      summary.stages.push_back(Execute(stage));
    } else {
      StageRun skipped;
      skipped.stage = stage;
      skipped.up_to_date = true;
      summary.stages.push_back(skipped);
    }
    if (stage == until) break;
  }
  WriteRunRecord();
  return summary;
}

void Pipeline::CheckHeldOutMattes() const {
  const ImageSet image_set = project_.LoadCameras();
  ProgressTask progress(progress_, "checking held-out mattes");
  for (int v = 0; v < image_set.NumViews(); ++v) {
    if (project_.IsHeldOut(image_set.views[v].name)) project_.LoadMatte(image_set, v);
    progress.Update(static_cast<double>(v + 1) / image_set.NumViews());
  }
}

StageRun Pipeline::RunStage(Stage stage) {
  StageRun run = Execute(stage);
  WriteRunRecord();
  return run;
}

StageRun Pipeline::Execute(Stage stage) {
  const auto start = std::chrono::steady_clock::now();
  const StageContext context{project_, options_, progress_};
  StageRun run = Definition(stage).run(context);
  run.stage = stage;
  run.seconds = SecondsSince(start);
  Record(run);
  return run;
}

}  // namespace sylva
