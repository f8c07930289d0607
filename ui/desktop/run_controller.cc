#include "ui/desktop/run_controller.h"

#include <QMetaObject>
#include <exception>

#include "core/util/check.h"
#include "ui/pipeline/project.h"

namespace sylva {

// Forwards the library's progress to the GUI thread (queued calls).
class RunController::Reporter : public ProgressReporter {
 public:
  explicit Reporter(RunController* controller) : controller_(controller) {}

  void Update(std::string_view task, double fraction) override {
    const int stage = stage_;
    const QString text = QString::fromUtf8(task.data(), static_cast<int>(task.size()));
    QMetaObject::invokeMethod(
        controller_,
        [c = controller_, stage, text, fraction] { emit c->Progress(stage, text, fraction); },
        Qt::QueuedConnection);
  }
  void SetStage(int stage) { stage_ = stage; }

 private:
  RunController* controller_;
  int stage_ = -1;  // -1 before the first stage; the worker thread's only
};

RunController::RunController(QObject* parent) : QObject(parent) {}

RunController::~RunController() {
  Cancel();
  Join();
}

void RunController::Join() {
  if (worker_.joinable()) worker_.join();
}

void RunController::Cancel() {
  if (running_ && reporter_) reporter_->RequestCancel();
}

void RunController::Start(const std::filesystem::path& root, const PipelineOptions& options,
                          Stage until, std::optional<Stage> single) {
  Launch([root, options] { return std::make_pair(Project::Open(root), options); }, until, single);
}

void RunController::StartSketch(const SketchSetup& setup) {
  Launch(
      [setup] {
        PipelineOptions options;
        OptionRegistry registry;
        RegisterPipelineOptions(&options, &registry);
        SetSketchDefaults(&registry);
        options.Check();
        return std::make_pair(CreateSketchProject(setup, options.sketch, registry), options);
      },
      AllStages().back().stage, std::nullopt);
}

void RunController::Launch(OpenJob open, Stage until, std::optional<Stage> single) {
  if (running_) return;
  Join();  // the previous worker has already sent Finished
  running_ = true;
  reporter_ = std::make_unique<Reporter>(this);
  Reporter* reporter = reporter_.get();
  worker_ = std::thread([this, reporter, open, until, single] {
    RunSummary summary;
    bool ok = false, cancelled = false;
    std::string message;
    try {
      const auto [project, options] = open();
      Pipeline pipeline(project, options, reporter);
      pipeline.SetStageStartCallback([this, reporter](Stage stage) {
        reporter->SetStage(static_cast<int>(stage));
        QMetaObject::invokeMethod(
            this, [this, stage] { emit StageStarted(static_cast<int>(stage)); },
            Qt::QueuedConnection);
      });
      if (single) {
        summary.stages.push_back(pipeline.RunStage(*single));
      } else {
        summary = pipeline.Run(until, false);
      }
      ok = true;
    } catch (const Cancelled&) {
      cancelled = true;
      message = "cancelled";
    } catch (const std::exception& error) {
      message = error.what();
    }
    QMetaObject::invokeMethod(
        this,
        [this, summary, ok, cancelled, message] {
          last_summary_ = summary;
          for (const StageRun& run : summary.stages) {
            emit StageFinished(static_cast<int>(run.stage), QString::fromStdString(run.brief),
                               run.up_to_date);
          }
          running_ = false;
          emit Finished(ok, cancelled, QString::fromStdString(message));
        },
        Qt::QueuedConnection);
  });
}

}  // namespace sylva
