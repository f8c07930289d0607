// The full-pipeline controller shared by the CLI, the batch runner and the
// desktop app: runs the stages of a project in order, re-running only those
// whose inputs changed (COLMAP-controller style, with progress and cancel).
//
// Stages: matte -> register -> density -> skeleton -> mesh -> report (the
// matte stage only when the project computes its mattes). Each stage's inputs
// (its options, the photo, camera and matte files it reads, the keys of the stages it
// builds on) are hashed into a key recorded in PROJECT/cache/stages.json with
// the stage's outputs; a stage is up to date when its key matches and its
// outputs exist. Every run writes the effective options and its profile (each
// stage's time, step by step: StageRun::profile) to PROJECT/out/run.json.
#ifndef SYLVA_UI_PIPELINE_PIPELINE_H_
#define SYLVA_UI_PIPELINE_PIPELINE_H_

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/util/progress.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/project.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {

struct StageInfo {
  Stage stage;
  const char* name;         // "density"
  const char* description;  // one line for help
};
// In pipeline order.
std::vector<StageInfo> AllStages();
StageInfo GetStageInfo(Stage stage);
// Throws InputError naming `source` for an unknown name.
Stage ParseStage(const std::string& name, const std::string& source);

struct RunSummary {
  std::vector<StageRun> stages;
  std::string BriefReport() const;
};

// What a stage reads, declared in one place (Pipeline::Inputs): its key is
// the hash of exactly this list, so a change to any of it makes the stage
// out of date, and nothing else does.
struct StageInputs {
  std::string version;  // the stage's algorithm version
  // Files, each with what it is ("photo", "matte", "held-out matte", ...);
  // keyed by path, size and modification time (a missing file counts too).
  std::vector<std::pair<std::string, std::filesystem::path>> files;
  // Option sections ("Density.") and single keys ("Skeleton.base").
  std::vector<std::string> options;
  std::vector<Stage> upstream;  // whose keys it includes
};

class Pipeline {
 public:
  // `options` must already hold the project's saved options and any
  // overrides; they are checked before any work starts.
  Pipeline(const Project& project, const PipelineOptions& options, ProgressReporter* progress);

  // Runs every stage up to and including `until` that is out of date (or
  // all of them with `force`; a forced run also starts every stage cold,
  // from none of the state earlier runs cached, so it depends only on the
  // inputs: StageContext::cold).
  RunSummary Run(Stage until, bool force);
  // Runs one stage now; its inputs from earlier stages must exist.
  StageRun RunStage(Stage stage);

  // Everything `stage` reads (for tests and tools: the app and batch show it).
  StageInputs Inputs(Stage stage) const;
  // The key that identifies the inputs of `stage`: the hash of Inputs()
  // with the files' stamps, the options' values and the upstream keys;
  // "not needed" for a stage the project does not need.
  std::string StageKey(Stage stage) const;
  bool IsUpToDate(Stage stage) const;

  // Called with each stage just before it runs (not for stages that are up
  // to date), e.g. so that a batch can tell in which stage a tree failed.
  void SetStageStartCallback(std::function<void(Stage)> callback) {
    on_stage_start_ = std::move(callback);
  }

 private:
  // `report_projections`: for the report stage (StageContext).
  StageRun Execute(Stage stage, bool cold = false,
                   const ReportProjections* report_projections = nullptr);
  // Reads the held-out views' mattes (only the report reads them) so a bad
  // one fails the run before any stage writes.
  void CheckHeldOutMattes() const;
  void Record(const StageRun& run) const;
  // out/run.json: the effective options and the run's profile (the stages'
  // times, step by step).
  void WriteRunRecord(const RunSummary& summary) const;

  const Project& project_;
  PipelineOptions options_;
  ProgressReporter* progress_;
  std::function<void(Stage)> on_stage_start_;
};

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PIPELINE_H_
