// The summary of a batch across its trees, read from what each tree's run
// left on disk (OUT_DIR/logs/<name>.json, and in the project
// cache/stages.json, out/report.json, out/metrics.json), so it can be
// rewritten at any time, also by a workflow engine after its jobs:
//
//   OUT_DIR/summary.csv   one row per tree of the manifest, in its order:
//                         status, stage and error, stage times, silhouette
//                         IoU per group of views, tree metrics, output paths
//                         (relative to OUT_DIR); empty cells where a figure
//                         does not exist (a tree that did not finish has no
//                         fidelity or metrics; a group without views no IoU)
//   OUT_DIR/summary.html  the same as a page with inline SVG plots (IoU per
//                         view, height and time per tree) and each tree's
//                         preview picture (linked, not embedded)
// Both are written atomically.
#ifndef SYLVA_UI_BATCH_BATCH_SUMMARY_H_
#define SYLVA_UI_BATCH_BATCH_SUMMARY_H_

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ui/batch/manifest.h"
#include "ui/batch/tree_run.h"

namespace sylva {

// One group of views' silhouette IoU (report.json's input_views, ...).
struct IouFigures {
  int num_views = 0;
  std::optional<double> mean;
  std::optional<double> min;
};

struct TreeSummary {
  std::string name;
  TreeStatus status;  // from logs/<name>.json ("not-run" if there is none)
  // Wall time of each stage's last run, by stage name (cache/stages.json).
  std::map<std::string, double> stage_seconds;
  // The rest only for a finished tree.
  IouFigures input, held_out, mesh_input, mesh_held_out;
  std::vector<double> input_view_ious, held_out_view_ious;  // density, per view
  std::string units;
  std::optional<double> height, crown_width, crown_volume_hull, crown_volume_density, dbh;
  std::optional<int> branches;  // branch axes of order >= 1
  std::optional<int> tips;
  std::vector<std::string> warning_codes;  // report.json's warnings
  // Output files that exist, relative to OUT_DIR, by column name
  // ("tree_glb", "report_html", "preview", ...).
  std::map<std::string, std::string> outputs;
};

// Reads a tree's summary; files that are missing or unreadable leave their
// figures empty (a summary never fails for one tree's files).
TreeSummary SummarizeTree(const ManifestTree& tree, const std::filesystem::path& out_dir);

std::string SummaryCsv(const std::vector<TreeSummary>& trees);
std::string SummaryHtml(const std::vector<TreeSummary>& trees, const Manifest& manifest);

// Summarizes every tree of the manifest and writes summary.csv and
// summary.html into `out_dir`.
void WriteBatchSummary(const Manifest& manifest, const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_BATCH_SUMMARY_H_
