#include "ui/batch/batch_summary.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <functional>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/file_util.h"
#include "ui/batch/csv.h"
#include "ui/pipeline/pipeline.h"

namespace sylva {
namespace {

// Output files of a project listed in the summary: column, path under out/.
const std::pair<const char*, const char*> kOutputs[] = {
    {"tree_glb", "tree.glb"},         {"tree_obj", "tree.obj"},
    {"bark_obj", "bark.obj"},         {"skeleton_json", "skeleton.json"},
    {"qsm_csv", "qsm.csv"},           {"density_vdb", "density.vdb"},
    {"metrics_json", "metrics.json"}, {"report_html", "report.html"}};

// Reads a JSON file, or null if it is missing or unreadable.
Json TryReadJson(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return nullptr;
  try {
    return ReadJsonFile(path);
  } catch (const std::exception&) {
    return nullptr;
  }
}

std::optional<double> Number(const Json& json, const char* key) {
  if (!json.is_object() || !json.contains(key) || !json[key].is_number()) return std::nullopt;
  return json[key].get<double>();
}

IouFigures ReadIou(const Json& report, const char* group) {
  IouFigures figures;
  if (!report.contains(group) || !report[group].is_object()) return figures;
  const Json& json = report[group];
  figures.num_views = static_cast<int>(Number(json, "num_views").value_or(0));
  figures.mean = Number(json, "mean_iou");
  figures.min = Number(json, "min_iou");
  return figures;
}

void ReadStageSeconds(const fs::path& project, TreeSummary* summary) {
  const Json records = TryReadJson(project / "cache" / "stages.json");
  if (!records.is_object()) return;
  for (const StageInfo& stage : AllStages()) {
    if (!records.contains(stage.name)) continue;
    if (const auto seconds = Number(records[stage.name], "seconds")) {
      summary->stage_seconds[stage.name] = *seconds;
    }
  }
}

void ReadReport(const fs::path& out, TreeSummary* summary) {
  const Json report = TryReadJson(out / "report.json");
  if (!report.is_object()) return;
  summary->input = ReadIou(report, "input_views");
  summary->held_out = ReadIou(report, "held_out_views");
  summary->mesh_input = ReadIou(report, "mesh_input_views");
  summary->mesh_held_out = ReadIou(report, "mesh_held_out_views");
  for (const Json& view : report.value("views", Json::array())) {
    const auto iou = Number(view, "iou");
    if (!iou) continue;
    (view.value("held_out", false) ? summary->held_out_view_ious : summary->input_view_ious)
        .push_back(*iou);
  }
  for (const Json& warning : report.value("warnings", Json::array())) {
    if (warning.is_object() && warning.contains("code") && warning["code"].is_string()) {
      summary->warning_codes.push_back(warning["code"].get<std::string>());
    }
  }
  const Json previews = report.value("previews", Json::array());
  std::error_code ec;
  if (!previews.empty() && previews[0].is_string() &&
      fs::is_regular_file(out / previews[0].get<std::string>(), ec)) {
    summary->outputs["preview"] =
        (fs::path(summary->name) / "out" / previews[0].get<std::string>()).generic_string();
  }
}

void ReadMetrics(const fs::path& out, TreeSummary* summary) {
  const Json metrics = TryReadJson(out / "metrics.json");
  if (!metrics.is_object()) return;
  summary->units = metrics.value("units", "");
  summary->height = Number(metrics, "height");
  summary->crown_width = Number(metrics, "crown_width");
  summary->crown_volume_hull = Number(metrics, "crown_volume_hull");
  summary->crown_volume_density = Number(metrics, "crown_volume_density");
  summary->dbh = Number(metrics, "dbh");
  if (const auto tips = Number(metrics, "num_tips")) summary->tips = static_cast<int>(*tips);
  if (!metrics.contains("orders") || !metrics["orders"].is_array()) return;
  int branches = 0;
  for (const Json& order : metrics["orders"]) {
    if (Number(order, "order").value_or(0) >= 1) {
      branches += static_cast<int>(Number(order, "num_branches").value_or(0));
    }
  }
  summary->branches = branches;
}

void ListOutputs(const fs::path& out_dir, TreeSummary* summary) {
  const fs::path project = out_dir / summary->name;
  std::error_code ec;
  if (fs::is_regular_file(project / "sylva.json", ec)) summary->outputs["project"] = summary->name;
  for (const auto& [column, file] : kOutputs) {
    if (fs::is_regular_file(project / "out" / file, ec)) {
      summary->outputs[column] = (fs::path(summary->name) / "out" / file).generic_string();
    }
  }
}

std::string Text(const std::optional<double>& value) {
  if (!value) return "";
  std::ostringstream text;
  text.precision(6);
  text << *value;
  return text.str();
}

std::string Text(const std::optional<int>& value) { return value ? std::to_string(*value) : ""; }

std::string Join(const std::vector<std::string>& parts, const char* separator) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : separator) + part;
  return text;
}

// The CSV's columns: header and value of each, in order.
struct Column {
  std::string name;
  std::function<std::string(const TreeSummary&)> value;
};

std::vector<Column> Columns() {
  std::vector<Column> columns = {
      {"name", [](const TreeSummary& t) { return t.name; }},
      {"status", [](const TreeSummary& t) { return t.status.status; }},
      {"stage", [](const TreeSummary& t) { return t.status.Finished() ? "" : t.status.stage; }},
      {"error", [](const TreeSummary& t) { return t.status.error; }},
      {"exit_code",
       [](const TreeSummary& t) {
         return t.status.exit_code >= 0 ? std::to_string(t.status.exit_code) : std::string();
       }},
      {"log", [](const TreeSummary& t) { return "logs/" + t.name + ".log"; }},
      {"finished", [](const TreeSummary& t) { return t.status.finished; }},
      {"seconds",
       [](const TreeSummary& t) { return Text(std::optional<double>(t.status.seconds)); }},
  };
  for (const StageInfo& stage : AllStages()) {
    const std::string name = stage.name;
    columns.push_back({"seconds_" + name, [name](const TreeSummary& t) {
                         const auto it = t.stage_seconds.find(name);
                         return it == t.stage_seconds.end() ? "" : Text(std::optional(it->second));
                       }});
  }
  const std::pair<const char*, IouFigures TreeSummary::*> groups[] = {
      {"input", &TreeSummary::input},
      {"held_out", &TreeSummary::held_out},
      {"mesh_input", &TreeSummary::mesh_input},
      {"mesh_held_out", &TreeSummary::mesh_held_out}};
  for (const auto& [group, member] : groups) {
    const std::string prefix = group;
    const auto m = member;
    columns.push_back({prefix + "_views", [m](const TreeSummary& t) {
                         return t.status.Finished() ? std::to_string((t.*m).num_views) : "";
                       }});
    columns.push_back(
        {prefix + "_mean_iou", [m](const TreeSummary& t) { return Text((t.*m).mean); }});
    columns.push_back(
        {prefix + "_min_iou", [m](const TreeSummary& t) { return Text((t.*m).min); }});
  }
  const std::pair<const char*, std::optional<double> TreeSummary::*> metrics[] = {
      {"height", &TreeSummary::height},
      {"crown_width", &TreeSummary::crown_width},
      {"crown_volume_hull", &TreeSummary::crown_volume_hull},
      {"crown_volume_density", &TreeSummary::crown_volume_density},
      {"dbh", &TreeSummary::dbh}};
  columns.push_back({"units", [](const TreeSummary& t) { return t.units; }});
  for (const auto& [name, member] : metrics) {
    const auto m = member;
    columns.push_back({name, [m](const TreeSummary& t) { return Text(t.*m); }});
  }
  columns.push_back({"branches", [](const TreeSummary& t) { return Text(t.branches); }});
  columns.push_back({"tips", [](const TreeSummary& t) { return Text(t.tips); }});
  columns.push_back({"warnings", [](const TreeSummary& t) { return Join(t.warning_codes, ";"); }});
  for (const char* output : {"project", "tree_glb", "tree_obj", "bark_obj", "skeleton_json",
                             "qsm_csv", "density_vdb", "metrics_json", "report_html", "preview"}) {
    const std::string key = output;
    columns.push_back({key, [key](const TreeSummary& t) {
                         const auto it = t.outputs.find(key);
                         return it == t.outputs.end() ? "" : it->second;
                       }});
  }
  return columns;
}

}  // namespace

TreeSummary SummarizeTree(const ManifestTree& tree, const fs::path& out_dir) {
  TreeSummary summary;
  summary.name = tree.name;
  summary.status = ReadTreeStatus(TreeStatusPath(out_dir, tree.name)).value_or(TreeStatus());
  summary.status.name = tree.name;
  const fs::path project = out_dir / tree.name;
  ReadStageSeconds(project, &summary);
  if (!summary.status.Finished()) return summary;
  ReadReport(project / "out", &summary);
  ReadMetrics(project / "out", &summary);
  ListOutputs(out_dir, &summary);
  return summary;
}

std::string SummaryCsv(const std::vector<TreeSummary>& trees) {
  const std::vector<Column> columns = Columns();
  std::vector<std::string> fields;
  for (const Column& column : columns) fields.push_back(column.name);
  std::string text = CsvLine(fields);
  for (const TreeSummary& tree : trees) {
    fields.clear();
    for (const Column& column : columns) fields.push_back(column.value(tree));
    text += CsvLine(fields);
  }
  return text;
}

void WriteBatchSummary(const Manifest& manifest, const fs::path& out_dir) {
  std::vector<TreeSummary> trees;
  for (const ManifestTree& tree : manifest.trees) trees.push_back(SummarizeTree(tree, out_dir));
  AtomicWriteString(out_dir / "summary.csv", SummaryCsv(trees));
  AtomicWriteString(out_dir / "summary.html", SummaryHtml(trees, manifest));
}

}  // namespace sylva
