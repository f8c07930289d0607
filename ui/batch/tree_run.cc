#include "ui/batch/tree_run.h"

#include <tbb/global_control.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <iostream>
#include <memory>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline.h"

namespace sylva {
namespace {

constexpr char kStatusFormat[] = "sylva-batch-tree";
constexpr int kStatusVersion = 1;

std::string LocalTime() {
  const std::time_t now = std::time(nullptr);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%S%z", std::localtime(&now));
  return buffer;
}

Json StatusJson(const TreeStatus& status) {
  return {{"format", kStatusFormat},
          {"version", kStatusVersion},
          {"name", status.name},
          {"status", status.status},
          {"stage", status.stage},
          {"error", status.error},
          {"exit_code", status.exit_code},
          {"pid", status.pid},
          {"inputs_key", status.inputs_key},
          {"started", status.started},
          {"finished", status.finished},
          {"seconds", status.seconds},
          {"stages_run", status.stages_run}};
}

TreeStatus ParseStatus(const Json& json, const std::string& source) {
  const JsonCursor root(json, source);
  CheckJsonFormat(root, kStatusFormat, kStatusVersion);
  TreeStatus status;
  status.name = root["name"].AsString();
  status.status = root["status"].AsString();
  status.stage = root["stage"].AsString();
  status.error = root["error"].AsString();
  status.exit_code = root["exit_code"].AsInt();
  status.pid = root["pid"].AsInt();
  status.inputs_key = root["inputs_key"].AsString();
  status.started = root["started"].AsString();
  status.finished = root["finished"].AsString();
  status.seconds = root["seconds"].AsDouble();
  const JsonCursor stages = root["stages_run"];
  for (size_t i = 0; i < stages.Size(); ++i) status.stages_run.push_back(stages[i].AsString());
  return status;
}

// The tree's run, step by step, keeping its status file current.
class TreeRunner {
 public:
  TreeRunner(const Manifest& manifest, const ManifestTree& tree, const fs::path& out_dir,
             const OptionList& batch_options, ProgressReporter* progress)
      : manifest_(manifest),
        tree_(tree),
        out_dir_(out_dir),
        batch_options_(batch_options),
        progress_(progress),
        status_path_(TreeStatusPath(out_dir, tree.name)) {}

  TreeStatus Run() {
    const auto start = std::chrono::steady_clock::now();
    Begin();
    try {
      RunSteps();
      status_.status = status_.stages_run.empty() ? "up-to-date" : "ok";
      status_.stage.clear();
      status_.exit_code = kTreeExitOk;
    } catch (const InputError& error) {
      Fail("failed", error.what(), kTreeExitBadInput);
    } catch (const Cancelled&) {
      Fail("interrupted", "interrupted", kTreeExitCancelled);
    } catch (const std::exception& error) {
      Fail("failed", std::string("internal error: ") + error.what(), kTreeExitError);
    }
    status_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    status_.finished = LocalTime();
    WriteTreeStatus(status_path_, status_);
    return status_;
  }

 private:
  // The status "running", keeping the inputs key of an existing project.
  void Begin() {
    const std::optional<TreeStatus> previous = ReadTreeStatus(status_path_);
    status_.name = tree_.name;
    status_.status = "running";
    status_.pid = static_cast<int>(getpid());
    status_.started = LocalTime();
    std::error_code ec;
    const bool exists = fs::exists(out_dir_ / tree_.name, ec);
    status_.inputs_key = exists && previous ? previous->inputs_key : tree_.InputsKey();
    SetStage("options");
  }

  void SetStage(const std::string& stage) {
    status_.stage = stage;
    WriteTreeStatus(status_path_, status_);
  }

  void Fail(const std::string& status, const std::string& message, int exit_code) {
    status_.status = status;
    status_.error = message;
    status_.exit_code = exit_code;
    std::cerr << "\nsylva: " << (exit_code == kTreeExitCancelled ? "" : "error: ") << message
              << "\n";
  }

  void RunSteps() {
    // Options first: a bad value fails the tree before anything is made.
    TreeOptions(nullptr, batch_options_, tree_, manifest_.path);
    SetStage("init");
    const Project project = OpenOrCreate();
    const PipelineOptions options = TreeOptions(&project, batch_options_, tree_, manifest_.path);
    std::unique_ptr<tbb::global_control> threads;
    if (options.general.num_threads > 0) {
      threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      options.general.num_threads);
    }
    SetStage("run");
    Pipeline pipeline(project, options, progress_);
    pipeline.SetStageStartCallback([this](Stage stage) {
      status_.stages_run.push_back(GetStageInfo(stage).name);
      SetStage(GetStageInfo(stage).name);
    });
    const RunSummary summary = pipeline.Run(AllStages().back().stage, /*force=*/false);
    std::cout << summary.BriefReport() << "Outputs in " << project.OutDir().string() << "/\n";
  }

  Project OpenOrCreate() const {
    const fs::path root = out_dir_ / tree_.name;
    std::error_code ec;
    if (!fs::exists(root, ec)) {
      const Project project = Project::Create(tree_.Setup(out_dir_));
      std::cout << "Created project " << root.string() << ": " << project.photo_names().size()
                << " photos (" << project.held_out().size() << " held out)\n";
      return project;
    }
    SYLVA_CHECK_INPUT(status_.inputs_key == tree_.InputsKey(), root.string())
        << "was made from other inputs than line " << tree_.line << " of "
        << manifest_.path.string()
        << " gives now (photos, cameras, mattes, held-out views or units); delete the folder "
           "or give the tree a new name to make it again";
    std::cout << "Project " << root.string() << " exists; running what is out of date\n";
    return Project::Open(root);
  }

  const Manifest& manifest_;
  const ManifestTree& tree_;
  const fs::path out_dir_;
  const OptionList& batch_options_;
  ProgressReporter* progress_;
  const fs::path status_path_;
  TreeStatus status_;
};

}  // namespace

fs::path BatchLogDir(const fs::path& out_dir) { return out_dir / "logs"; }

fs::path TreeLogPath(const fs::path& out_dir, const std::string& name) {
  return BatchLogDir(out_dir) / (name + ".log");
}

fs::path TreeStatusPath(const fs::path& out_dir, const std::string& name) {
  return BatchLogDir(out_dir) / (name + ".json");
}

std::optional<TreeStatus> ReadTreeStatus(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  try {
    return ParseStatus(ReadJsonFile(path), path.string());
  } catch (const InputError&) {
    return std::nullopt;
  }
}

void WriteTreeStatus(const fs::path& path, const TreeStatus& status) {
  WriteJsonFile(path, StatusJson(status));
}

PipelineOptions TreeOptions(const Project* project, const OptionList& batch_options,
                            const ManifestTree& tree, const fs::path& manifest_path) {
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  if (project != nullptr) project->ApplySavedOptions(&registry);
  for (const auto& [key, value] : batch_options) registry.Set(key, value, "--" + key);
  const std::string row = manifest_path.string() + ":" + std::to_string(tree.line);
  for (const auto& [key, value] : tree.options) registry.Set(key, value, row);
  try {
    options.Check();
  } catch (const InputError& error) {
    // Name the manifest line when the tree's own options are at fault.
    bool own = false;
    for (const auto& option : tree.options) own = own || error.source() == option.first;
    if (own) SYLVA_INPUT_ERROR(row + ": " + error.source()) << error.message();
    throw;
  }
  return options;
}

TreeStatus RunTree(const Manifest& manifest, const ManifestTree& tree, const fs::path& out_dir,
                   const OptionList& batch_options, ProgressReporter* progress) {
  return TreeRunner(manifest, tree, out_dir, batch_options, progress).Run();
}

bool TreeIsUpToDate(const Manifest& manifest, const ManifestTree& tree, const fs::path& out_dir,
                    const OptionList& batch_options) {
  const std::optional<TreeStatus> status = ReadTreeStatus(TreeStatusPath(out_dir, tree.name));
  if (!status || !status->Finished() || status->inputs_key != tree.InputsKey()) return false;
  try {
    const Project project = Project::Open(out_dir / tree.name);
    const PipelineOptions options = TreeOptions(&project, batch_options, tree, manifest.path);
    const Pipeline pipeline(project, options, nullptr);
    for (const StageInfo& stage : AllStages()) {
      if (pipeline.StageKey(stage.stage) == "not needed") continue;
      if (!pipeline.IsUpToDate(stage.stage)) return false;
    }
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace sylva
