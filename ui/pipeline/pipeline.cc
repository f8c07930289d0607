#include "ui/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <sstream>

#include "core/io/json_util.h"
#include "core/io/vdb_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/threading.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/report.h"

namespace sylva {
namespace {

// Bump a stage's version when its algorithm changes its outputs, so old
// results are recomputed.
constexpr char kDensityVersion[] = "density/1";
constexpr char kReportVersion[] = "report/1";
constexpr char kSylvaVersion[] = "0.1.0";

const std::vector<StageInfo> kStages = {
    {Stage::kDensity, "density",
     "back-project the mattes into a voxel density grid (out/density.vdb)"},
    {Stage::kReport, "report",
     "per-view fidelity of the reconstruction against the mattes (out/report.json)"},
};

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The options of the given sections, as canonical JSON text.
std::string SectionsText(const PipelineOptions& options, const std::vector<std::string>& keys) {
  PipelineOptions copy = options;
  OptionRegistry registry;
  RegisterPipelineOptions(&copy, &registry);
  std::string text;
  for (const std::string& key : keys) text += key + "=" + registry.Get(key) + ";";
  return text;
}

std::vector<std::string> KeysOfSection(const std::string& section) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  std::vector<std::string> keys;
  for (const auto& entry : registry.entries()) {
    if (entry.key.rfind(section + ".", 0) == 0) keys.push_back(entry.key);
  }
  return keys;
}

Json LoadStageRecords(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Json::object();
  try {
    Json json = ReadJsonFile(path);
    return json.is_object() ? json : Json::object();
  } catch (const InputError& error) {
    // The cache is safe to delete; a corrupt one only means re-running.
    SYLVA_LOG(kWarning) << error.what() << " (ignored; stages will re-run)";
    return Json::object();
  }
}

std::vector<FloatImage> LoadMattes(const Project& project, const ImageSet& image_set,
                                   ProgressTask* progress) {
  std::vector<FloatImage> mattes(image_set.NumViews());
  progress->Update(0.0);
  ParallelForFirstError(image_set.NumViews(), [&](int v) {
    progress->CheckCancelled();
    mattes[v] = project.LoadMatte(image_set, v);
  });
  progress->Update(1.0);
  return mattes;
}

// The views used for the reconstruction (all but the held-out ones).
ImageSet InputViews(const Project& project, const ImageSet& image_set) {
  ImageSet inputs = image_set;
  inputs.views.clear();
  for (const View& view : image_set.views) {
    if (!project.IsHeldOut(view.name)) inputs.views.push_back(view);
  }
  return inputs;
}

std::string LocalTime() {
  const std::time_t now = std::time(nullptr);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%S%z", std::localtime(&now));
  return buffer;
}

}  // namespace

const std::vector<StageInfo>& AllStages() { return kStages; }

const StageInfo& GetStageInfo(Stage stage) {
  for (const StageInfo& info : kStages) {
    if (info.stage == stage) return info;
  }
  SYLVA_CHECK(false) << "unknown stage";
  return kStages.front();
}

Stage ParseStage(const std::string& name, const std::string& source) {
  for (const StageInfo& info : kStages) {
    if (name == info.name) return info.stage;
  }
  std::string names;
  for (const StageInfo& info : kStages) names += (names.empty() ? "" : ", ") + std::string(info.name);
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
  std::string text;
  for (const fs::path& file : project_.CameraFiles()) {
    text += file.string() + ":" + HexString(FileStamp(file)) + ";";
  }
  const ImageSet image_set = project_.LoadCameras();
  for (const View& view : image_set.views) {
    const bool held_out = project_.IsHeldOut(view.name);
    if (stage == Stage::kDensity && held_out) continue;
    const fs::path matte = project_.MattePath(view.name);
    text += view.name + (held_out ? "(held out)" : "") + "=" + matte.string() + ":" +
            HexString(FileStamp(matte)) + ";";
  }
  if (stage == Stage::kDensity) {
    text = std::string(kDensityVersion) + ";" + text + SectionsText(options_, KeysOfSection("Density"));
  } else {
    text = std::string(kReportVersion) + ";" + text +
           SectionsText(options_, KeysOfSection("Report")) + "density=" + StageKey(Stage::kDensity);
  }
  return HexString(Fnv1a64(text));
}

bool Pipeline::IsUpToDate(Stage stage) const {
  const Json records = LoadStageRecords(project_.CacheDir() / "stages.json");
  const std::string name = GetStageInfo(stage).name;
  if (!records.contains(name)) return false;
  const Json& record = records[name];
  if (!record.contains("key") || record["key"] != StageKey(stage)) return false;
  std::error_code ec;
  for (const auto& output : record.value("outputs", Json::array())) {
    if (!output.is_string() || !fs::is_regular_file(project_.root() / output.get<std::string>(), ec)) {
      return false;
    }
  }
  return true;
}

void Pipeline::Record(const StageRun& run) const {
  const fs::path path = project_.CacheDir() / "stages.json";
  Json records = LoadStageRecords(path);
  Json outputs = Json::array();
  for (const fs::path& output : run.outputs) {
    outputs.push_back(fs::relative(output, project_.root()).generic_string());
  }
  records[GetStageInfo(run.stage).name] = {{"key", StageKey(run.stage)},
                                           {"outputs", outputs},
                                           {"seconds", run.seconds},
                                           {"summary", run.brief},
                                           {"finished", LocalTime()}};
  WriteJsonFile(path, records);
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
  for (const StageInfo& info : kStages) {
    if (force || !IsUpToDate(info.stage)) to_run.push_back(info.stage);
    if (info.stage == until) break;
  }
  const auto runs = [&](Stage stage) {
    return std::find(to_run.begin(), to_run.end(), stage) != to_run.end();
  };
  // A bad matte must fail the run before any stage writes. Each stage checks
  // the mattes it reads before writing; only the held-out views' are read by
  // the report alone, after the density stage has written its grid.
  if (runs(Stage::kDensity) && runs(Stage::kReport)) CheckHeldOutMattes();
  RunSummary summary;
  for (const StageInfo& info : kStages) {
    if (runs(info.stage)) {
      summary.stages.push_back(Execute(info.stage));
    } else {
      StageRun skipped;
      skipped.stage = info.stage;
      skipped.up_to_date = true;
      summary.stages.push_back(skipped);
    }
    if (info.stage == until) break;
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
  StageRun run = stage == Stage::kDensity ? RunDensity() : RunReport();
  run.stage = stage;
  run.seconds = SecondsSince(start);
  Record(run);
  return run;
}

StageRun Pipeline::RunDensity() {
  ProgressTask progress(progress_, "density: reading mattes", 0.0, 0.1);
  const ImageSet image_set = InputViews(project_, project_.LoadCameras());
  const std::vector<FloatImage> mattes = LoadMattes(project_, image_set, &progress);
  DensitySummary summary;
  DensityGrid grid = ReconstructDensity(image_set, mattes, options_.density, progress_, &summary);
  grid.SetMetadata("units", project_.units());
  StageRun run;
  run.brief = summary.BriefReport();
  run.outputs = {project_.OutDir() / "density.vdb"};
  WriteDensityGrid(run.outputs[0], grid);
  return run;
}

StageRun Pipeline::RunReport() {
  const fs::path density_path = project_.OutDir() / "density.vdb";
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(density_path, ec), density_path.string())
      << "no density grid yet; run the density stage first ('sylva run')";
  const DensityGrid grid = ReadDensityGrid(density_path);
  const ImageSet image_set = project_.LoadCameras();
  ProgressTask progress(progress_, "report: reading mattes");
  const std::vector<FloatImage> mattes = LoadMattes(project_, image_set, &progress);
  std::vector<bool> held_out;
  for (const View& view : image_set.views) held_out.push_back(project_.IsHeldOut(view.name));
  FidelityReport report = ComputeFidelity(grid, image_set, mattes, held_out, options_.report);
  report.units = project_.units();
  const Json records = LoadStageRecords(project_.CacheDir() / "stages.json");
  const std::string density_brief =
      records.contains("density") ? records["density"].value("summary", "") : "";
  StageRun run;
  run.brief = report.BriefReport();
  run.outputs = WriteFidelityReport(report, density_brief, options_.report, project_.OutDir());
  return run;
}

}  // namespace sylva
