// Runs the pipeline (ui/pipeline/pipeline.h) in a worker thread so the
// event loop never blocks (COLMAP's controller threads): the whole pipeline
// up to a stage (only out-of-date stages run, the pipeline's cache decides)
// or one stage. Progress and the end arrive as queued signals in the GUI
// thread; Cancel asks the library's ProgressReporter to stop, and the stage
// then throws Cancelled at its next check, having written nothing (stages
// write their outputs atomically at the end).
#ifndef SYLVA_UI_DESKTOP_RUN_CONTROLLER_H_
#define SYLVA_UI_DESKTOP_RUN_CONTROLLER_H_

#include <QObject>
#include <QString>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <thread>

#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/sketch_project.h"

namespace sylva {

class RunController : public QObject {
  Q_OBJECT

 public:
  explicit RunController(QObject* parent = nullptr);
  // Cancels a run in progress and waits for it.
  ~RunController() override;

  bool IsRunning() const { return running_; }

  // Starts a run on the project at `root` with `options` (checked in the
  // worker; an error ends the run with Finished(false, ...)): every stage
  // up to `until` that is out of date, or `single` alone. No-op if running.
  void Start(const std::filesystem::path& root, const PipelineOptions& options, Stage until,
             std::optional<Stage> single = std::nullopt);
  // `sylva sketch`'s work in the worker: creates the sketch project
  // `setup` (CreateSketchProject with the sketch defaults,
  // SetSketchDefaults) and runs every stage with its saved options. The
  // project's root is `setup.root`. No-op if running.
  void StartSketch(const SketchSetup& setup);
  // Asks the running stage to stop (returns at once).
  void Cancel();

  // The summary of the last finished run (stages that completed).
  const RunSummary& last_summary() const { return last_summary_; }

 signals:
  void StageStarted(int stage);
  // `fraction` of the running stage's current task `task`, in [0, 1];
  // stage -1 for checks before the first stage.
  void Progress(int stage, const QString& task, double fraction);
  void StageFinished(int stage, const QString& brief, bool up_to_date);
  // ok: every stage asked for ran or was up to date; `message`: the error
  // or "cancelled" otherwise.
  void Finished(bool ok, bool cancelled, const QString& message);

 private:
  class Reporter;
  // The project to run and its options, made in the worker.
  using OpenJob = std::function<std::pair<Project, PipelineOptions>()>;
  void Launch(OpenJob open, Stage until, std::optional<Stage> single);
  void Join();

  std::unique_ptr<Reporter> reporter_;
  std::thread worker_;
  bool running_ = false;
  RunSummary last_summary_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_RUN_CONTROLLER_H_
