// One tree of a batch, run in this process: `sylva batch MANIFEST OUT_DIR
// --only NAME`, which the batch runs as a child process per tree (so that a
// tree that crashes cannot take the others with it) and a workflow engine
// runs per job. It makes OUT_DIR/<name>/ as `sylva init` would (unless it
// exists), runs the pipeline as `sylva run` would (the stage cache skips what
// is up to date, so a killed run resumes), and records how it went in
// OUT_DIR/logs/<name>.json:
//
// { "format": "sylva-batch-tree", "version": 1, "name": "oak-17",
//   "status": "ok", "stage": "", "error": "", "exit_code": 0, "pid": 4711,
//   "inputs_key": "9a0c...", "started": "...", "finished": "...",
//   "seconds": 12.5, "stages_run": ["density", ...] }
#ifndef SYLVA_UI_BATCH_TREE_RUN_H_
#define SYLVA_UI_BATCH_TREE_RUN_H_

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/util/progress.h"
#include "ui/batch/manifest.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/project.h"

namespace sylva {

namespace fs = std::filesystem;

// Exit codes of a tree's run, as the `sylva` command's.
constexpr int kTreeExitOk = 0;
constexpr int kTreeExitError = 1;        // a failure inside sylva
constexpr int kTreeExitBadInput = 2;     // bad files or options
constexpr int kTreeExitCancelled = 130;  // interrupted

// Where a tree is, or how its last run ended.
struct TreeStatus {
  std::string name;
  // "running" (or killed while running), "ok" (ran to the end),
  // "up-to-date" (every stage was up to date: nothing ran), "failed" (exit
  // code 2 for bad input, 1 for an internal error), "crashed" (killed by a
  // signal), "interrupted" (cancelled with Ctrl-C), "not-run".
  std::string status = "not-run";
  // Where it is or where it failed: "options" (the tree's options), "init"
  // (making the project), "run" (checks before the first stage), or a stage.
  std::string stage;
  std::string error;  // the error message ("" unless failed)
  int exit_code = -1;
  int pid = 0;             // of the process running the tree
  std::string inputs_key;  // ManifestTree::InputsKey() of the project's inputs
  std::string started;     // local time, ISO 8601
  std::string finished;
  double seconds = 0.0;                 // wall time of the run
  std::vector<std::string> stages_run;  // the stages that ran (not up to date)

  bool Finished() const { return status == "ok" || status == "up-to-date"; }
};

// OUT_DIR/logs/, and in it a tree's log (<name>.log: what its run printed)
// and status (<name>.json).
fs::path BatchLogDir(const fs::path& out_dir);
fs::path TreeLogPath(const fs::path& out_dir, const std::string& name);
fs::path TreeStatusPath(const fs::path& out_dir, const std::string& name);

// nullopt if the file is missing or unreadable (a status is only a record).
std::optional<TreeStatus> ReadTreeStatus(const fs::path& path);
void WriteTreeStatus(const fs::path& path, const TreeStatus& status);  // atomically

using OptionList = std::vector<std::pair<std::string, std::string>>;

// The options a tree runs with: the defaults, the project's saved options
// (`project` may be null), the batch's, then the tree's own; checked.
// Throws InputError naming the option (and the manifest line for the
// tree's own).
PipelineOptions TreeOptions(const Project* project, const OptionList& batch_options,
                            const ManifestTree& tree, const fs::path& manifest_path);

// Runs the tree in this process. Prints what `sylva init` and `sylva run`
// print to stdout, and an error as "sylva: error: ..." to stderr; never
// throws for the tree's own failures (they go into the status). Returns the
// status written last.
TreeStatus RunTree(const Manifest& manifest, const ManifestTree& tree, const fs::path& out_dir,
                   const OptionList& batch_options, ProgressReporter* progress);

// Whether the tree's last run finished, from the inputs the manifest gives
// now, and every stage is still up to date with these options: running it
// again would do nothing. False on any doubt.
bool TreeIsUpToDate(const Manifest& manifest, const ManifestTree& tree, const fs::path& out_dir,
                    const OptionList& batch_options);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_TREE_RUN_H_
