// What every pipeline stage gets (the project, the options, progress) and
// returns (a StageRun), plus the helpers stages share. Each stage is a plain
// function (density_stage.cc, skeleton_stage.cc, ...) that reads its inputs
// from the project folder, calls the algorithm modules, and writes its
// outputs atomically at the end, so a failed or cancelled stage changes
// nothing.
#ifndef SYLVA_UI_PIPELINE_STAGE_CONTEXT_H_
#define SYLVA_UI_PIPELINE_STAGE_CONTEXT_H_

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/types/attractor_graph.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "core/util/warning.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/project.h"

namespace sylva {

enum class Stage { kMatte, kRegister, kDensity, kAttract, kSkeleton, kMesh, kReport };

// One figure of a stage's summary (Ceres' Summary fields, as data): a count,
// a time or a score under a stable snake_case key, with its unit ("" for a
// plain number or a fraction).
struct StageFigure {
  std::string key;
  double value = 0.0;
  std::string unit;
};

// One timed step of a stage's profile (reading inputs, the solve, writing
// outputs, ...), with the sub-steps its algorithm reports. Sub-steps are
// timed inside their step; what is left (setup between them) is not listed,
// so they may sum to less than the step.
struct StageStep {
  std::string name;      // snake_case: "read_mattes", "solve"
  double seconds = 0.0;  // wall time
  std::vector<StageStep> steps;

  // Appends a sub-step and returns this step (to chain).
  StageStep& Add(const std::string& step_name, double step_seconds);
};

// "read_mattes 0.12 s, reconstruct 2.1 s (bounds 0.5, solve 1.0), write
// 0.05 s"; "" without steps.
std::string ProfileText(const std::vector<StageStep>& steps);

// Times the consecutive steps of a stage: each Lap() ends the step that
// began at the previous Lap() (or at construction) and appends it to
// `steps`. Not thread-safe; one per stage run.
// Wall seconds since `start`.
double SecondsSince(std::chrono::steady_clock::time_point start);

// Runs `work` and returns its wall time in seconds (for steps that run side
// by side, whose times StepClock's laps cannot tell apart).
template <typename Work>
double TimeOf(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return SecondsSince(start);
}

class StepClock {
 public:
  explicit StepClock(std::vector<StageStep>* steps);
  // Ends the current step as `name`; returns it, to add its sub-steps.
  StageStep& Lap(const std::string& name);

 private:
  std::vector<StageStep>* steps_;
  std::chrono::steady_clock::time_point start_;
};

struct StageRun {
  Stage stage = Stage::kDensity;
  bool up_to_date = false;  // skipped: inputs unchanged since the last run
  double seconds = 0.0;
  std::string brief;  // the stage's BriefReport(), for humans
  // The run as figures, for the CLI, the report and tests: the stage's own in
  // the order it adds them, then "seconds" (the stage's wall time); kept in
  // cache/stages.json, so an up-to-date stage still reports them.
  std::vector<StageFigure> figures;
  // What the user must know about the result (core/util/warning.h); kept in
  // cache/stages.json, so an up-to-date stage still reports them.
  std::vector<Warning> warnings;
  std::vector<std::filesystem::path> outputs;
  // Where the stage's time went, step by step (StepClock); kept in
  // cache/stages.json and written to out/run.json with every run.
  std::vector<StageStep> profile;

  void AddFigure(const std::string& key, double value, const std::string& unit = "");
  // The value of the figure under `key`; nullopt if there is none.
  std::optional<double> Figure(const std::string& key) const;
};

// "key=value unit, ..." (whole numbers as integers, other values with 4
// significant digits); "" without figures.
std::string FiguresText(const std::vector<StageFigure>& figures);

// The density's projection into every view, as the report stage makes it,
// under the key the report stage files it by (report_stage.cc).
struct ReportProjections {
  std::string key;
  std::vector<FloatImage> images;
};

struct StageContext {
  const Project& project;
  const PipelineOptions& options;
  ProgressReporter* progress;
  // Start from scratch: use none of the state that earlier runs left in the
  // cache folder to go faster (the density solve's warm start, the attractor
  // graphs of unchanged views), so the outputs depend only on the inputs.
  // Set for forced runs (`sylva run --force`).
  bool cold = false;
  // The report stage's density projections, made in this run while the
  // stages between the density and the report ran (Pipeline::Run), or null.
  // The report stage takes them when their key is its own.
  const ReportProjections* report_projections = nullptr;

  std::filesystem::path Out(const std::string& name) const { return project.OutDir() / name; }
  // An earlier stage's output; InputError naming it if it does not exist.
  std::filesystem::path RequireOutput(const std::string& name, const char* stage) const;
  // The views used for the reconstruction (all but the held-out ones).
  ImageSet InputViews() const;
  // Every view's matte, decoded in parallel (first view's error thrown).
  // `edited`: with the density edits mixed in (Project::LoadEditedMatte), as
  // every stage from the density on reads them.
  std::vector<FloatImage> LoadMattes(const ImageSet& image_set, const std::string& task,
                                     bool edited = true) const;
  // The world units of the registered cameras: the register stage's (set by
  // WorldFrame.known_height or a loose-camera file's height), else the
  // project's.
  std::string Units() const;
  // The BriefReport() recorded by an earlier stage ("" if none).
  std::string RecordedBrief(const std::string& stage_name) const;
  // The warnings recorded by an earlier stage (none if it has not run).
  std::vector<Warning> RecordedWarnings(const std::string& stage_name) const;
  // The figures recorded by an earlier stage (none if it has not run).
  std::vector<StageFigure> RecordedFigures(const std::string& stage_name) const;
};

StageRun RunMatteStage(const StageContext& context);
StageRun RunRegisterStage(const StageContext& context);
StageRun RunDensityStage(const StageContext& context);
StageRun RunAttractStage(const StageContext& context);
StageRun RunSkeletonStage(const StageContext& context);
StageRun RunMeshStage(const StageContext& context);
StageRun RunReportStage(const StageContext& context);
// The report stage's density projections for the density.vdb that is there
// now (needs no output of the stages after the density). Throws what the
// report stage would throw.
ReportProjections MakeReportProjections(const StageContext& context);

// The attractor graphs the attract stage wrote, one per view of `views`
// (empty where a view has none), from out/attractors/attractors.json.
std::vector<AttractorGraph2D> LoadAttractorGraphs(const Project& project, const ImageSet& views);

// The values of the options under `prefixes` (Section. or Section.field), as
// canonical text for cache keys.
std::string OptionsText(const PipelineOptions& options, const std::vector<std::string>& prefixes);

// A file's identity in a cache key: its path (relative to the project for
// files inside it, so a moved project stays up to date) and its stamp (size
// and modification time; 0 for a missing file).
std::string FileKey(const Project& project, const std::filesystem::path& file);

// The warnings recorded for a stage in cache/stages.json (none if the stage
// has not run or the cache is unreadable).
std::vector<Warning> ReadRecordedWarnings(const Project& project, const std::string& stage_name);

// The BriefReport() recorded for a stage in cache/stages.json ("" if the
// stage has not run or the cache is unreadable).
std::string ReadRecordedBrief(const Project& project, const std::string& stage_name);

// The figures recorded for a stage in cache/stages.json (none if the stage
// has not run or the cache is unreadable).
std::vector<StageFigure> ReadRecordedFigures(const Project& project, const std::string& stage_name);

// cache/stages.json as JSON text ("{}" if missing or unreadable: the cache is
// safe to delete, a corrupt one only means re-running).
std::string ReadStageRecordsText(const Project& project);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_STAGE_CONTEXT_H_
