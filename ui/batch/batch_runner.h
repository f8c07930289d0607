// `sylva batch`: every tree of a manifest becomes the project OUT_DIR/<name>/,
// each run in a child process of the same program (`sylva batch MANIFEST
// OUT_DIR --only NAME`, ui/batch/tree_run.h), up to `jobs` at a time. Trees
// that finished before and are still up to date are skipped without starting
// a process; a tree that fails (bad input, internal error, crash) is recorded
// with its stage, message and log, and the others go on. Progress (trees
// done / running / failed, with an ETA) goes to stderr; at the end, and after
// each tree, OUT_DIR/summary.csv and summary.html are rewritten
// (ui/batch/batch_summary.h).
#ifndef SYLVA_UI_BATCH_BATCH_RUNNER_H_
#define SYLVA_UI_BATCH_BATCH_RUNNER_H_

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "ui/batch/manifest.h"
#include "ui/batch/tree_run.h"

namespace sylva {

// Exit code of `sylva batch` when the batch ran but at least one tree failed
// (0 when every tree finished; 2 for a bad manifest or option, nothing run;
// 130 when interrupted).
constexpr int kBatchExitTreesFailed = 3;

struct BatchOptions {
  int jobs = 1;  // trees run at once, >= 1
  // --Section.field=value options for every tree (a tree's own override them).
  OptionList options;
  std::string log_level;  // passed to each tree's run ("" = default)
  // The program run per tree (the sylva binary); empty = this program.
  std::filesystem::path program;
};

struct BatchResult {
  int num_trees = 0;
  int num_ok = 0;           // ran to the end
  int num_up_to_date = 0;   // skipped: finished before, nothing to do
  int num_failed = 0;       // failed or crashed
  int num_interrupted = 0;  // cancelled, or never started after an interrupt
  double seconds = 0.0;
  // 0 all finished, kBatchExitTreesFailed, or 130 when interrupted.
  int ExitCode() const;
  std::string BriefReport() const;
};

// Runs the batch. `interrupt` (set from a SIGINT handler) stops starting
// trees and interrupts the running ones. Throws InputError only for problems
// of the batch itself (OUT_DIR not writable, another batch running on it).
BatchResult RunBatch(const Manifest& manifest, const std::filesystem::path& out_dir,
                     const BatchOptions& options, const std::atomic<bool>* interrupt);

// Checks the batch-wide options (names and values) before anything runs;
// throws InputError naming the option.
void CheckBatchOptions(const OptionList& options);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_BATCH_RUNNER_H_
