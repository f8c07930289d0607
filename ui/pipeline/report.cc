#include "ui/pipeline/report.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/file_util.h"
#include "core/util/html.h"
#include "core/util/threading.h"
#include "mesh/tree_preview.h"

namespace sylva {

namespace {

// Comparison pictures are enlarged (nearest neighbour) to at least this size.
constexpr int kMinPictureSize = 256;

// A value with 3 decimals, or "none" if absent.
std::string Fixed(const std::optional<double>& value) {
  if (!value) return "none";
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << *value;
  return out.str();
}

std::string GroupLine(const char* label, const FidelityGroup& group) {
  return std::string("  ") + label + " (" + std::to_string(group.num_views) + "): IoU mean " +
         Fixed(group.mean_iou) + ", min " + Fixed(group.min_iou) + "; precision " +
         Fixed(group.mean_precision) + ", recall " + Fixed(group.mean_recall) + "\n";
}

// White: both; red: predicted only; blue: matte only; dark: neither.
FloatImage ComparisonPicture(const FloatImage& predicted, const FloatImage& observed,
                             const ReportOptions& options) {
  const int scale = std::max(1, (kMinPictureSize + predicted.width() - 1) / predicted.width());
  FloatImage picture(predicted.width() * scale, predicted.height() * scale, 3);
  for (int y = 0; y < picture.height(); ++y) {
    for (int x = 0; x < picture.width(); ++x) {
      const bool p = predicted.at(x / scale, y / scale) >= options.opacity_threshold;
      const bool m = observed.at(x / scale, y / scale) >= options.matte_threshold;
      const float grey = 0.25f * observed.at(x / scale, y / scale);
      picture.at(x, y, 0) = p ? (m ? 0.95f : 0.9f) : grey;
      picture.at(x, y, 1) = p && m ? 0.95f : grey;
      picture.at(x, y, 2) = m ? (p ? 0.95f : 0.9f) : grey;
    }
  }
  return picture;
}

Json ScoresJson(const SilhouetteScores& s) {
  return {{"iou", s.iou},
          {"precision", s.precision},
          {"recall", s.recall},
          {"true_positive", s.true_positive},
          {"false_positive", s.false_positive},
          {"false_negative", s.false_negative}};
}

Json OptionalJson(const std::optional<double>& value) {
  return value ? Json(*value) : Json(nullptr);
}

// Absent scores (no views in the group) are null.
Json GroupJson(const FidelityGroup& group) {
  return {{"num_views", group.num_views},
          {"mean_iou", OptionalJson(group.mean_iou)},
          {"min_iou", OptionalJson(group.min_iou)},
          {"mean_precision", OptionalJson(group.mean_precision)},
          {"mean_recall", OptionalJson(group.mean_recall)}};
}

Json WarningsJson(const std::vector<Warning>& warnings) {
  Json json = Json::array();
  for (const Warning& warning : warnings) {
    json.push_back({{"code", warning.code}, {"message", warning.message}});
    if (!warning.subject.empty()) json.back()["subject"] = warning.subject;
  }
  return json;
}

Json ViewJson(const ViewFidelity& view) {
  Json json = ScoresJson(view.scores);
  if (!view.warnings.empty()) json["warnings"] = WarningsJson(view.warnings);
  json["name"] = view.name;
  json["held_out"] = view.held_out;
  if (view.prior) json["prior"] = true;
  json["downsample_factor"] = view.downsample_factor;
  json["compared_size"] = {view.width, view.height};
  if (view.has_mesh) json["mesh"] = ScoresJson(view.mesh_scores);
  return json;
}

// <preview_dir>/preview_<k>.png, relative to the report.
fs::path PreviewPath(const FidelityReport& report, size_t k) {
  return fs::path(report.preview_dir) / ("preview_" + std::to_string(k) + ".png");
}

// {stage: [{"key", "value", "unit"}, ...]}
Json StageFiguresJson(
    const std::vector<std::pair<std::string, std::vector<StageFigure>>>& stage_figures) {
  Json json = Json::object();
  for (const auto& [stage, figures] : stage_figures) {
    Json list = Json::array();
    for (const StageFigure& figure : figures) {
      list.push_back({{"key", figure.key}, {"value", figure.value}, {"unit", figure.unit}});
    }
    json[stage] = list;
  }
  return json;
}

Json ReportJson(const FidelityReport& report, const std::map<std::string, std::string>& briefs) {
  Json views = Json::array();
  for (const ViewFidelity& view : report.views) views.push_back(ViewJson(view));
  const Box3d& b = report.bounds;
  Json json = {{"format", "sylva-report"},
               {"version", 3},
               {"what",
                "silhouettes of the projected density grid and of the rendered mesh against the "
                "mattes, per view; input and held-out views separately"},
               {"units", report.units},
               {"density",
                {{"voxel_size", report.voxel_size},
                 {"active_voxels", report.num_voxels},
                 {"bounds_min", {b.min().x(), b.min().y(), b.min().z()}},
                 {"bounds_max", {b.max().x(), b.max().y(), b.max().z()}}}},
               {"input_views", GroupJson(report.input)},
               {"held_out_views", GroupJson(report.held_out)},
               {"prior_views", report.NumPriorViews()},
               {"stages", briefs},
               {"warnings", WarningsJson(report.warnings)},
               {"views", views}};
  if (report.has_tree) {
    json["mesh_input_views"] = GroupJson(report.mesh_input);
    json["mesh_held_out_views"] = GroupJson(report.mesh_held_out);
    json["mesh_triangles"] = report.num_mesh_triangles;
  }
  // The tree's figures as out/metrics.json has them (with their sources).
  if (report.has_metrics) json["tree"] = Json::parse(report.metrics.ToJson());
  Json previews = Json::array();
  for (size_t k = 0; k < report.previews.size(); ++k) {
    previews.push_back(PreviewPath(report, k).generic_string());
  }
  json["previews"] = previews;
  json["stage_figures"] = StageFiguresJson(report.stage_figures);
  return json;
}

// out/report/<kind>/<view name>.png
fs::path PicturePath(const std::string& kind, const std::string& view_name) {
  return fs::path("report") / kind / fs::path(view_name).replace_extension(".png");
}

std::string ImageCell(const std::string& kind, const std::string& view_name) {
  return "<td><img src=\"" + HtmlEscape(PicturePath(kind, view_name).generic_string()) + "\"></td>";
}

// One row of the Tree section's table; `value` already formatted.
std::string MetricRow(const std::string& name, const std::string& value,
                      const std::string& source) {
  return "<tr><td>" + HtmlEscape(name) + "</td><td>" + HtmlEscape(value) + "</td><td>" +
         HtmlEscape(source) + "</td></tr>\n";
}

std::string Number(double value, const std::string& unit) {
  std::ostringstream out;
  out << std::setprecision(4) << value << (unit.empty() ? "" : " " + unit);
  return out.str();
}

// The previews beside the tree's figures from out/metrics.json, each with
// its source (measured from the photos, or a prior).
std::string TreeSectionHtml(const FidelityReport& report) {
  if (report.previews.empty() && !report.has_metrics) return "";
  std::ostringstream html;
  html << "<h2>Tree</h2>\n<div>";
  for (size_t k = 0; k < report.previews.size(); ++k) {
    html << "<img class=\"preview\" src=\"" << PreviewPath(report, k).generic_string() << "\">";
  }
  html << "</div>\n";
  if (!report.has_metrics) return html.str();
  const TreeMetricsReport& m = report.metrics;
  const std::string volume = m.units + "^3";
  const auto row = [&](const std::string& name, const std::string& value, const char* figure) {
    return MetricRow(name, value, m.SourceOf(figure));
  };
  html << "<table>\n<tr><th>figure</th><th>value</th><th>source</th></tr>\n"
       << row("height", Number(m.height, m.units), "height")
       << row("crown base height", Number(m.crown_base_height, m.units), "crown_base_height")
       << row("crown depth", Number(m.crown_depth, m.units), "crown_depth")
       << row("crown width", Number(m.crown_width, m.units), "crown_width")
       << row("crown volume (convex hull)", Number(m.crown_volume_hull, volume),
              "crown_volume_hull")
       << row("crown volume (density)",
              m.crown_volume_density ? Number(*m.crown_volume_density, volume) : "none",
              "crown_volume_density")
       << row("DBH", m.dbh ? Number(*m.dbh, m.units) : "none: " + m.dbh_note, "dbh")
       << row("tips", std::to_string(m.num_tips), "num_tips")
       << row("total branch length", Number(m.total_length, m.units), "total_length");
  for (const OrderMetrics& order : m.orders) {
    std::string value =
        std::to_string(order.num_branches) + " branches, " + Number(order.total_length, m.units);
    if (order.num_angles > 0) value += ", mean angle " + Number(order.mean_angle_deg, "deg");
    html << row("order " + std::to_string(order.order), value, "orders");
  }
  html << "</table>\n";
  if (report.views.empty()) {
    html << "<p>Figures from metrics.json, each with its source.</p>\n";
    return html.str();
  }
  html << "<p>Figures from out/metrics.json. Sources: <i>measured</i> from the photos "
          "(the density and the skeleton that follows it); <i>prior</i>: set by the model "
          "(the particle count and merging for the branching, the pipe model for the radii), "
          "not measured.</p>\n";
  return html.str();
}

// The stages' figures as a table (nothing if there are none).
std::string StageFiguresHtml(
    const std::vector<std::pair<std::string, std::vector<StageFigure>>>& stage_figures) {
  if (stage_figures.empty()) return "";
  std::string html = "<h2>Stages</h2>\n<table>\n<tr><th>stage</th><th>figures</th></tr>\n";
  for (const auto& [stage, figures] : stage_figures) {
    html += "<tr><td>" + HtmlEscape(stage) + "</td><td>" + HtmlEscape(FiguresText(figures)) +
            "</td></tr>\n";
  }
  return html + "</table>\n";
}

// The warnings as a list (nothing if there are none).
std::string WarningsHtml(const std::vector<Warning>& warnings) {
  if (warnings.empty()) return "";
  std::string html = "<h2>Warnings</h2>\n<ul>\n";
  for (const Warning& warning : warnings) {
    html += "<li class=\"warning\"><b>" + HtmlEscape(warning.code) +
            "</b>: " + HtmlEscape(warning.message) + "</li>\n";
  }
  return html + "</ul>\n";
}

std::string ReportHtml(const FidelityReport& report,
                       const std::map<std::string, std::string>& briefs) {
  std::ostringstream html;
  html << std::fixed << std::setprecision(3)
       << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>sylva report</title>"
          "<style>body{font-family:sans-serif}td,th{padding:4px 8px}img{width:256px;"
          "image-rendering:pixelated}img.preview{width:320px;image-rendering:auto}"
          ".warning{color:#b00}</style></head>"
          "<body>\n<h1>sylva report</h1>\n<pre>"
       << HtmlEscape(report.BriefReport()) << "</pre>\n"
       << WarningsHtml(report.warnings) << TreeSectionHtml(report)
       << StageFiguresHtml(report.stage_figures) << "<ul>";
  for (const auto& [stage, brief] : briefs) {
    html << "<li><b>" << HtmlEscape(stage) << "</b>: " << HtmlEscape(brief) << "</li>\n";
  }
  html << "</ul>\n";
  if (report.views.empty()) {
    html << "</body></html>\n";
    return html.str();
  }
  html << "<p>Comparisons: white = both, red = reconstruction only, blue = matte only."
       << "</p>\n<table><tr><th>view</th><th>held out</th><th>density IoU</th><th>mesh IoU</th>"
       << "<th>density vs matte</th><th>mesh vs matte</th><th>mesh</th></tr>\n";
  for (const ViewFidelity& view : report.views) {
    html << "<tr><td>" << HtmlEscape(view.name);
    for (const Warning& warning : view.warnings) {
      html << "<br><span class=\"warning\">" << HtmlEscape(warning.code) << "</span>";
    }
    html << "</td><td>"
         << (view.held_out ? "yes"
             : view.prior  ? "prior (not a photo)"
                           : "")
         << "</td><td>" << view.scores.iou << "</td><td>";
    if (view.has_mesh) html << view.mesh_scores.iou;
    html << "</td>" << ImageCell("density", view.name);
    if (view.has_mesh) html << ImageCell("mesh", view.name) << ImageCell("render", view.name);
    html << "</tr>\n";
  }
  html << "</table></body></html>\n";
  return html.str();
}

// out/report/{density,mesh,render}/<view>.png (those the view has); returns
// the paths written.
std::vector<fs::path> WriteViewPictures(const ViewFidelity& view, const ReportOptions& options,
                                        const fs::path& out_dir) {
  std::vector<fs::path> written = {out_dir / PicturePath("density", view.name)};
  WriteImage(written.back(), ComparisonPicture(view.predicted, view.observed, options));
  if (!view.has_mesh) return written;
  written.push_back(out_dir / PicturePath("mesh", view.name));
  WriteImage(written.back(), ComparisonPicture(view.mesh_coverage, view.observed, options));
  if (view.mesh_render.empty()) return written;
  written.push_back(out_dir / PicturePath("render", view.name));
  WriteImage(written.back(), view.mesh_render);
  return written;
}

// The comparison settings of the Report options.
ViewFidelityOptions FidelityOptions(const ReportOptions& options) {
  ViewFidelityOptions fidelity;
  fidelity.opacity_threshold = options.opacity_threshold;
  fidelity.matte_threshold = options.matte_threshold;
  fidelity.pixels_per_voxel = options.pixels_per_voxel;
  fidelity.mesh_samples_per_axis = options.mesh_samples_per_axis;
  fidelity.render_pictures = options.write_images;
  return fidelity;
}

}  // namespace

std::string FidelityReport::BriefReport() const {
  std::string text;
  if (views.empty()) {
    text = "No photos to compare the tree with (it was made without photos).\n";
  } else {
    text = "Fidelity (silhouettes vs mattes, at about the grid's resolution):\n";
    if (input.num_views > 0) text += GroupLine("density, input views", input);
    if (held_out.num_views > 0) text += GroupLine("density, held-out views", held_out);
    if (mesh_input.num_views > 0) text += GroupLine("mesh, input views", mesh_input);
    if (mesh_held_out.num_views > 0) text += GroupLine("mesh, held-out views", mesh_held_out);
    if (held_out.num_views == 0) text += "  no held-out views\n";
  }
  if (const int priors = NumPriorViews(); priors > 0) {
    text += "  " + std::to_string(priors) +
            " prior view(s) (made up, not photographed: a drawing's depth prior) are not in "
            "these figures\n";
  }
  if (has_metrics) {
    const TreeMetricsReport& m = metrics;
    std::ostringstream out;
    out << "Tree (out/metrics.json): height " << Number(m.height, m.units) << ", crown base "
        << Number(m.crown_base_height, m.units) << ", crown width "
        << Number(m.crown_width, m.units) << " (" << m.SourceOf("height") << "); DBH "
        << (m.dbh ? Number(*m.dbh, m.units) : "none") << " (" << m.SourceOf("dbh")
        << "); branch length " << Number(m.total_length, m.units) << ", branches per order";
    for (const OrderMetrics& order : m.orders) out << " " << order.num_branches;
    out << " (" << m.SourceOf("orders") << ").\n";
    text += out.str();
  }
  return text;
}

FidelityReport ComputeFidelity(const DensityGrid& grid, const ImageSet& image_set,
                               const std::vector<FloatImage>& mattes,
                               const std::vector<bool>& held_out, const ReportOptions& options,
                               std::vector<FloatImage>* projections) {
  FidelityReport report;
  report.voxel_size = grid.voxel_size();
  report.num_voxels = grid.NumActiveVoxels();
  report.bounds = grid.ActiveWorldBounds();
  report.views = ComputeDensityViewFidelity(grid, image_set, mattes, held_out,
                                            FidelityOptions(options), projections);
  report.input = SummariseViews(report.views, false, false);
  report.held_out = SummariseViews(report.views, true, false);
  return report;
}

int FidelityReport::NumPriorViews() const {
  return static_cast<int>(
      std::count_if(views.begin(), views.end(), [](const ViewFidelity& v) { return v.prior; }));
}

void MarkPriorViews(const std::vector<std::string>& names, FidelityReport* report) {
  for (ViewFidelity& view : report->views) {
    view.prior = std::find(names.begin(), names.end(), view.name) != names.end();
  }
  report->input = SummariseViews(report->views, false, false);
  report->held_out = SummariseViews(report->views, true, false);
  if (!report->has_tree || report->num_mesh_triangles == 0) return;
  report->mesh_input = SummariseViews(report->views, false, true);
  report->mesh_held_out = SummariseViews(report->views, true, true);
}

namespace {

// A poor fit's warning: its code, what reproduces the mattes, and what is
// wrong when the silhouettes miss the mattes' foreground or exceed it.
struct PoorFit {
  const char* code;
  const char* what;
  const FidelityGroup FidelityReport::*group;
  const char* misses;
  const char* exceeds;
};

constexpr PoorFit kPoorFits[] = {
    {"poor-density-fit", "the density", &FidelityReport::input,
     "it lacks structure the mattes show (thinner than the voxels: raise Density.resolution; or "
     "shown by some mattes and not others: a wrong or inconsistent matte, or cameras that "
     "disagree)",
     "it covers more than the mattes show (soft or missing mattes, cameras that disagree, or "
     "bounds too loose)"},
    {"poor-mesh-fit", "the tree's silhouette", &FidelityReport::mesh_input,
     "branches or foliage the mattes show are missing (the skeleton did not reach them, or the "
     "radii are too thin)",
     "the tree is larger than the mattes show (radii or leaves too large, or branches outside the "
     "crown)"}};

}  // namespace

std::vector<Warning> FidelityWarnings(const FidelityReport& report, const ReportOptions& options) {
  std::vector<Warning> warnings;
  for (const PoorFit& fit : kPoorFits) {
    const FidelityGroup& group = report.*fit.group;
    if (!group.mean_iou || *group.mean_iou >= options.poor_fit_iou) continue;
    // "mean IoU 0.42 ... (precision 0.91, recall 0.44)", and from the weaker
    // of precision and recall, what the silhouettes do wrong.
    const bool missing = *group.mean_recall < *group.mean_precision;
    warnings.push_back(
        {fit.code, std::string(fit.what) + " reproduces the mattes poorly, mean IoU " +
                       Fixed(group.mean_iou) + " over " + std::to_string(group.num_views) +
                       " input views (precision " + Fixed(group.mean_precision) + ", recall " +
                       Fixed(group.mean_recall) + "): " + (missing ? fit.misses : fit.exceeds)});
  }
  return warnings;
}

void AddWarnings(const std::vector<Warning>& warnings, FidelityReport* report) {
  for (const Warning& warning : warnings) {
    report->warnings.push_back(warning);
    for (ViewFidelity& view : report->views) {
      if (!warning.subject.empty() && warning.subject == view.name)
        view.warnings.push_back(warning);
    }
  }
}

void AddMeshFidelity(const TriangleMesh& mesh, const ImageSet& image_set,
                     const ReportOptions& options, FidelityReport* report) {
  report->has_tree = true;
  report->num_mesh_triangles = mesh.NumTriangles();
  AddMeshViewFidelity(mesh, image_set, FidelityOptions(options), &report->views);
  if (mesh.NumTriangles() == 0) return;
  report->mesh_input = SummariseViews(report->views, false, true);
  report->mesh_held_out = SummariseViews(report->views, true, true);
}

std::vector<FloatImage> RenderReportPreviews(const TriangleMesh& bark, const LeafInstances* leaves,
                                             const ReportOptions& options) {
  options.Check();
  const bool has_leaves = leaves != nullptr && !leaves->instances.empty();
  if (!options.previews || (bark.NumTriangles() == 0 && !has_leaves)) return {};
  TreePreviewOptions preview;
  preview.width = preview.height = options.preview_size;
  preview.samples_per_axis = options.preview_samples_per_axis;
  return RenderTreePreviews(bark, has_leaves ? leaves : nullptr, preview);
}

std::vector<fs::path> WritePreviewPngs(const std::vector<FloatImage>& previews,
                                       const fs::path& dir) {
  std::vector<fs::path> written;
  for (size_t k = 0; k < previews.size(); ++k) {
    written.push_back(dir / ("preview_" + std::to_string(k) + ".png"));
  }
  ParallelForFirstError(static_cast<int>(previews.size()),
                        [&](int k) { WriteImage(written[k], previews[k]); });
  return written;
}

std::vector<fs::path> WriteFidelityReport(const FidelityReport& report,
                                          const std::map<std::string, std::string>& stage_briefs,
                                          const ReportOptions& options, const fs::path& out_dir) {
  std::vector<fs::path> written = WritePreviewPngs(report.previews, out_dir / report.preview_dir);
  if (options.write_images) {
    // Each view's pictures are encoded in parallel; the list keeps view order.
    std::vector<std::vector<fs::path>> pictures(report.views.size());
    ParallelForFirstError(static_cast<int>(report.views.size()), [&](int v) {
      pictures[v] = WriteViewPictures(report.views[v], options, out_dir);
    });
    for (const std::vector<fs::path>& paths : pictures) {
      written.insert(written.end(), paths.begin(), paths.end());
    }
    AtomicWriteString(out_dir / "report.html", ReportHtml(report, stage_briefs));
    written.push_back(out_dir / "report.html");
  }
  // report.json last: its presence means the report is complete.
  WriteJsonFile(out_dir / "report.json", ReportJson(report, stage_briefs));
  written.push_back(out_dir / "report.json");
  return written;
}

}  // namespace sylva
