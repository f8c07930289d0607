#include "ui/pipeline/report.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/file_util.h"
#include "reconstruct/density/opacity_projection.h"

namespace sylva {
namespace {

// Comparison pictures are enlarged (nearest neighbour) to at least this size.
constexpr int kMinPictureSize = 256;

FidelityGroup Summarise(const std::vector<ViewFidelity>& views, bool held_out) {
  FidelityGroup group;
  group.min_iou = 1.0;
  for (const ViewFidelity& view : views) {
    if (view.held_out != held_out) continue;
    ++group.num_views;
    group.mean_iou += view.scores.iou;
    group.min_iou = std::min(group.min_iou, view.scores.iou);
    group.mean_precision += view.scores.precision;
    group.mean_recall += view.scores.recall;
  }
  if (group.num_views == 0) return FidelityGroup();
  group.mean_iou /= group.num_views;
  group.mean_precision /= group.num_views;
  group.mean_recall /= group.num_views;
  return group;
}

std::string GroupLine(const char* label, const FidelityGroup& group) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << "  " << label << " (" << group.num_views
      << "): IoU mean " << group.mean_iou << ", min " << group.min_iou << "; precision "
      << group.mean_precision << ", recall " << group.mean_recall << "\n";
  return out.str();
}

// White: both; red: predicted only; blue: matte only; black: neither.
FloatImage ComparisonPicture(const ViewFidelity& view, const ReportOptions& options) {
  const int scale = std::max(1, (kMinPictureSize + view.width - 1) / view.width);
  FloatImage picture(view.width * scale, view.height * scale, 3);
  for (int y = 0; y < picture.height(); ++y) {
    for (int x = 0; x < picture.width(); ++x) {
      const bool p = view.predicted.at(x / scale, y / scale) >= options.opacity_threshold;
      const bool m = view.observed.at(x / scale, y / scale) >= options.matte_threshold;
      const float grey = 0.25f * view.observed.at(x / scale, y / scale);
      picture.at(x, y, 0) = p ? (m ? 0.95f : 0.9f) : grey;
      picture.at(x, y, 1) = p && m ? 0.95f : grey;
      picture.at(x, y, 2) = m ? (p ? 0.95f : 0.9f) : grey;
    }
  }
  return picture;
}

Json GroupJson(const FidelityGroup& group) {
  return {{"num_views", group.num_views},   {"mean_iou", group.mean_iou},
          {"min_iou", group.min_iou},       {"mean_precision", group.mean_precision},
          {"mean_recall", group.mean_recall}};
}

Json ReportJson(const FidelityReport& report, const std::string& density_brief) {
  Json views = Json::array();
  for (const ViewFidelity& view : report.views) {
    views.push_back({{"name", view.name},
                     {"held_out", view.held_out},
                     {"downsample_factor", view.downsample_factor},
                     {"compared_size", {view.width, view.height}},
                     {"iou", view.scores.iou},
                     {"precision", view.scores.precision},
                     {"recall", view.scores.recall},
                     {"true_positive", view.scores.true_positive},
                     {"false_positive", view.scores.false_positive},
                     {"false_negative", view.scores.false_negative}});
  }
  return {{"format", "sylva-report"},
          {"version", 1},
          {"what", "silhouettes of the projected density grid against the mattes"},
          {"units", report.units},
          {"density",
           {{"voxel_size", report.voxel_size},
            {"active_voxels", report.num_voxels},
            {"bounds_min", {report.bounds.min().x(), report.bounds.min().y(), report.bounds.min().z()}},
            {"bounds_max", {report.bounds.max().x(), report.bounds.max().y(), report.bounds.max().z()}},
            {"summary", density_brief}}},
          {"input_views", GroupJson(report.input)},
          {"held_out_views", GroupJson(report.held_out)},
          {"views", views}};
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

fs::path PictureRelativePath(const std::string& view_name) {
  return fs::path("report") / fs::path(view_name).replace_extension(".png");
}

std::string ReportHtml(const FidelityReport& report, const std::string& density_brief) {
  std::ostringstream html;
  html << std::fixed << std::setprecision(3)
       << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>sylva report</title>"
          "<style>body{font-family:sans-serif}td,th{padding:4px 8px}img{width:256px;"
          "image-rendering:pixelated}</style></head><body>\n<h1>sylva fidelity report</h1>\n"
       << "<p>" << HtmlEscape(density_brief) << "</p>\n<pre>" << HtmlEscape(report.BriefReport())
       << "</pre>\n<p>Pictures: white = both, red = reconstruction only, blue = matte only.</p>\n"
       << "<table><tr><th>view</th><th>held out</th><th>IoU</th><th>precision</th>"
          "<th>recall</th><th>comparison</th></tr>\n";
  for (const ViewFidelity& view : report.views) {
    html << "<tr><td>" << HtmlEscape(view.name) << "</td><td>" << (view.held_out ? "yes" : "")
         << "</td><td>" << view.scores.iou << "</td><td>" << view.scores.precision << "</td><td>"
         << view.scores.recall << "</td><td><img src=\""
         << HtmlEscape(PictureRelativePath(view.name).generic_string()) << "\"></td></tr>\n";
  }
  html << "</table></body></html>\n";
  return html.str();
}

}  // namespace

std::string FidelityReport::BriefReport() const {
  std::string text = "Fidelity (projected density vs mattes, at about the grid's resolution):\n";
  text += GroupLine("input views", input);
  if (held_out.num_views > 0) text += GroupLine("held-out views", held_out);
  return text;
}

FidelityReport ComputeFidelity(const DensityGrid& grid, const ImageSet& image_set,
                               const std::vector<FloatImage>& mattes,
                               const std::vector<bool>& held_out,
                               const ReportOptions& options) {
  FidelityReport report;
  const OpacityProjector projector(grid);
  report.voxel_size = grid.voxel_size();
  report.num_voxels = grid.NumActiveVoxels();
  report.bounds = grid.ActiveWorldBounds();
  const Eigen::Vector3d center =
      grid.IsEmpty() ? grid.origin() : Eigen::Vector3d(report.bounds.center());
  for (int v = 0; v < image_set.NumViews(); ++v) {
    const ViewSampling sampling =
        MakeViewSampling(image_set, v, center, grid.voxel_size(), options.pixels_per_voxel, 1);
    ViewFidelity view;
    view.name = image_set.views[v].name;
    view.held_out = held_out[v];
    view.downsample_factor = sampling.factor;
    view.width = sampling.width();
    view.height = sampling.height();
    view.predicted = projector.Render(image_set, v, sampling);
    view.observed = DownsampleBox(mattes[v], sampling.factor);
    view.scores = CompareSilhouettes(view.predicted, view.observed,
                                     static_cast<float>(options.opacity_threshold),
                                     static_cast<float>(options.matte_threshold));
    report.views.push_back(std::move(view));
  }
  report.input = Summarise(report.views, false);
  report.held_out = Summarise(report.views, true);
  return report;
}

std::vector<fs::path> WriteFidelityReport(const FidelityReport& report,
                                          const std::string& density_brief,
                                          const ReportOptions& options, const fs::path& out_dir) {
  std::vector<fs::path> written;
  if (options.write_images) {
    for (const ViewFidelity& view : report.views) {
      const fs::path path = out_dir / PictureRelativePath(view.name);
      WriteImage(path, ComparisonPicture(view, options));
      written.push_back(path);
    }
    AtomicWriteString(out_dir / "report.html", ReportHtml(report, density_brief));
    written.push_back(out_dir / "report.html");
  }
  // report.json last: its presence means the report is complete.
  WriteJsonFile(out_dir / "report.json", ReportJson(report, density_brief));
  written.push_back(out_dir / "report.json");
  return written;
}

}  // namespace sylva
