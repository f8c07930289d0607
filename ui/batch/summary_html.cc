// summary.html of a batch (ui/batch/batch_summary.h): a self-contained page,
// plots drawn as inline SVG, preview pictures linked by relative path.
#include <algorithm>
#include <cmath>
#include <ctime>
#include <iterator>
#include <sstream>

#include "core/util/html.h"
#include "ui/batch/batch_summary.h"
#include "ui/pipeline/pipeline.h"

namespace sylva {
namespace {

// Plot layout, in SVG pixels.
constexpr int kPlotHeight = 180;   // the bars' area
constexpr int kMarginLeft = 56;    // axis labels
constexpr int kMarginBottom = 90;  // rotated tree names
constexpr int kMarginTop = 12;
constexpr int kBarPitch = 18;  // per tree
constexpr int kMinPlotWidth = 360;
constexpr int kHistogramBins = 20;  // IoU bins of 0.05
constexpr int kThumbnailSize = 96;

const char* const kStageColors[] = {"#8c6d31", "#6b6ecf", "#3182bd", "#9c9ede",
                                    "#31a354", "#e6550d", "#969696"};

std::string Fixed(double value, int digits) {
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(digits);
  text << value;
  return text.str();
}

std::string Optional(const std::optional<double>& value, int digits) {
  return value ? Fixed(*value, digits) : "";
}

// A "nice" axis maximum at or above `value` (1, 2 or 5 times a power of 10).
double NiceMax(double value) {
  if (!(value > 0)) return 1.0;
  const double power = std::pow(10.0, std::floor(std::log10(value)));
  for (double step : {1.0, 2.0, 5.0, 10.0}) {
    if (step * power >= value) return step * power;
  }
  return 10.0 * power;
}

// A tick label: whole numbers whole, others with at most 2 decimals.
std::string Label(double value) {
  std::string text = Fixed(value, value == std::round(value) ? 0 : 2);
  if (text.find('.') != std::string::npos && text.back() == '0') text.pop_back();
  return text;
}

// The y axis: a line, ticks at 0, half and the maximum, and a label.
void YAxis(double max, const std::string& label, std::ostringstream* svg) {
  *svg << "<line x1='" << kMarginLeft << "' y1='" << kMarginTop << "' x2='" << kMarginLeft
       << "' y2='" << kMarginTop + kPlotHeight << "' stroke='#444'/>";
  for (double f : {0.0, 0.5, 1.0}) {
    const double y = kMarginTop + kPlotHeight * (1.0 - f);
    const double v = max * f;
    *svg << "<text x='" << kMarginLeft - 4 << "' y='" << Fixed(y + 4, 1) << "' text-anchor='end'>"
         << Label(v) << "</text><line x1='" << kMarginLeft << "' x2='" << kMarginLeft + 4000
         << "' y1='" << Fixed(y, 1) << "' y2='" << Fixed(y, 1) << "' stroke='#eee'/>";
  }
  *svg << "<text x='12' y='" << kMarginTop + kPlotHeight / 2 << "' transform='rotate(-90 12 "
       << kMarginTop + kPlotHeight / 2 << ")' text-anchor='middle'>" << HtmlEscape(label)
       << "</text>";
}

std::string SvgOpen(int width) {
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='"
      << kMarginTop + kPlotHeight + kMarginBottom << "' font-size='11' font-family='sans-serif'>";
  return svg.str();
}

// One bar per tree, stacked from `segments` (value per tree per segment).
std::string BarChart(const std::vector<TreeSummary>& trees,
                     const std::vector<std::vector<double>>& segments,
                     const std::vector<std::string>& colors, const std::string& label) {
  double max = 0.0;
  for (size_t t = 0; t < trees.size(); ++t) {
    double total = 0.0;
    for (const auto& segment : segments) total += segment[t];
    max = std::max(max, total);
  }
  max = NiceMax(max);
  const int width =
      std::max(kMinPlotWidth, kMarginLeft + kBarPitch * static_cast<int>(trees.size()) + 10);
  std::ostringstream svg;
  svg << SvgOpen(width);
  YAxis(max, label, &svg);
  for (size_t t = 0; t < trees.size(); ++t) {
    const double x = kMarginLeft + 4 + kBarPitch * static_cast<double>(t);
    double base = kMarginTop + kPlotHeight;
    for (size_t s = 0; s < segments.size(); ++s) {
      const double h = kPlotHeight * segments[s][t] / max;
      if (h <= 0.0) continue;
      base -= h;
      svg << "<rect x='" << Fixed(x, 1) << "' y='" << Fixed(base, 1) << "' width='" << kBarPitch - 4
          << "' height='" << Fixed(h, 1) << "' fill='" << colors[s] << "'/>";
    }
    const double label_y = kMarginTop + kPlotHeight + 8;
    svg << "<text x='" << Fixed(x + 6, 1) << "' y='" << Fixed(label_y, 1)
        << "' transform='rotate(60 " << Fixed(x + 6, 1) << " " << Fixed(label_y, 1) << ")'>"
        << HtmlEscape(trees[t].name) << "</text>";
  }
  svg << "</svg>";
  return svg.str();
}

// Histograms of per-view IoU, one colour per group, side by side per bin.
std::string IouHistogram(const std::vector<std::vector<double>>& groups,
                         const std::vector<std::string>& colors) {
  std::vector<std::vector<int>> counts(groups.size(), std::vector<int>(kHistogramBins, 0));
  int max = 1;
  for (size_t g = 0; g < groups.size(); ++g) {
    for (double iou : groups[g]) {
      const int bin = std::clamp(static_cast<int>(iou * kHistogramBins), 0, kHistogramBins - 1);
      max = std::max(max, ++counts[g][bin]);
    }
  }
  const int pitch = 24;
  const int width = kMarginLeft + pitch * kHistogramBins + 20;
  std::ostringstream svg;
  svg << SvgOpen(width);
  YAxis(NiceMax(max), "views", &svg);
  const double bar = (pitch - 4.0) / static_cast<double>(groups.size());
  for (int b = 0; b < kHistogramBins; ++b) {
    const double x = kMarginLeft + 2 + pitch * b;
    for (size_t g = 0; g < groups.size(); ++g) {
      if (counts[g][b] == 0) continue;
      const double h = kPlotHeight * counts[g][b] / NiceMax(max);
      svg << "<rect x='" << Fixed(x + bar * g, 1) << "' y='"
          << Fixed(kMarginTop + kPlotHeight - h, 1) << "' width='" << Fixed(bar, 1) << "' height='"
          << Fixed(h, 1) << "' fill='" << colors[g] << "'><title>" << counts[g][b]
          << "</title></rect>";
    }
    if (b % 4 == 0) {
      svg << "<text x='" << x << "' y='" << kMarginTop + kPlotHeight + 14
          << "' text-anchor='middle'>" << Fixed(b / static_cast<double>(kHistogramBins), 1)
          << "</text>";
    }
  }
  svg << "<text x='" << kMarginLeft + pitch * kHistogramBins / 2 << "' y='"
      << kMarginTop + kPlotHeight + 32 << "' text-anchor='middle'>silhouette IoU</text></svg>";
  return svg.str();
}

std::string Legend(const std::vector<std::string>& names, const std::vector<std::string>& colors) {
  std::ostringstream html;
  html << "<p class='legend'>";
  for (size_t i = 0; i < names.size(); ++i) {
    html << "<span style='background:" << colors[i] << "'></span>" << HtmlEscape(names[i]) << " ";
  }
  html << "</p>";
  return html.str();
}

std::string Plots(const std::vector<TreeSummary>& trees) {
  std::vector<double> input, held_out;
  for (const TreeSummary& tree : trees) {
    input.insert(input.end(), tree.input_view_ious.begin(), tree.input_view_ious.end());
    held_out.insert(held_out.end(), tree.held_out_view_ious.begin(), tree.held_out_view_ious.end());
  }
  std::ostringstream html;
  html << "<h2>Silhouette IoU of the density, per view</h2>"
       << Legend({"input views (" + std::to_string(input.size()) + ")",
                  "held-out views (" + std::to_string(held_out.size()) + ")"},
                 {"#3182bd", "#e6550d"})
       << IouHistogram({input, held_out}, {"#3182bd", "#e6550d"});
  std::vector<double> heights;
  for (const TreeSummary& tree : trees) heights.push_back(tree.height.value_or(0.0));
  std::string units = "height";
  for (const TreeSummary& tree : trees) {
    if (!tree.units.empty()) units = "height (" + tree.units + ")";
  }
  html << "<h2>Height per tree</h2>" << BarChart(trees, {heights}, {"#31a354"}, units);
  std::vector<std::vector<double>> times;
  std::vector<std::string> names, colors;
  for (const StageInfo& stage : AllStages()) {
    std::vector<double> seconds;
    for (const TreeSummary& tree : trees) {
      const auto it = tree.stage_seconds.find(stage.name);
      seconds.push_back(it == tree.stage_seconds.end() ? 0.0 : it->second);
    }
    names.push_back(stage.name);
    colors.push_back(kStageColors[times.size() % std::size(kStageColors)]);
    times.push_back(seconds);
  }
  html << "<h2>Time per tree, by stage (last run of each stage)</h2>" << Legend(names, colors)
       << BarChart(trees, times, colors, "seconds");
  return html.str();
}

std::string TreeRow(const TreeSummary& tree) {
  const auto output = [&](const char* key) {
    const auto it = tree.outputs.find(key);
    return it == tree.outputs.end() ? std::string() : it->second;
  };
  std::ostringstream html;
  const std::string status = tree.status.status;
  html << "<tr class='" << HtmlEscape(status) << "'><td>";
  if (!output("preview").empty()) {
    html << "<a href='" << HtmlEscape(output("preview")) << "'><img src='"
         << HtmlEscape(output("preview")) << "' width='" << kThumbnailSize << "' height='"
         << kThumbnailSize << "' alt=''></a>";
  }
  html << "</td><td>";
  if (!output("report_html").empty()) {
    html << "<a href='" << HtmlEscape(output("report_html")) << "'>" << HtmlEscape(tree.name)
         << "</a>";
  } else {
    html << HtmlEscape(tree.name);
  }
  html << "</td><td>" << HtmlEscape(status) << "</td><td>"
       << HtmlEscape(tree.status.Finished() ? "" : tree.status.stage) << "</td><td class='error'>"
       << HtmlEscape(tree.status.error) << "</td><td>" << Optional(tree.input.mean, 3)
       << "</td><td>" << Optional(tree.input.min, 3) << "</td><td>"
       << Optional(tree.held_out.mean, 3) << "</td><td>" << Optional(tree.held_out.min, 3)
       << "</td><td>" << Optional(tree.height, 3) << "</td><td>" << Optional(tree.crown_width, 3)
       << "</td><td>" << Optional(tree.crown_volume_hull, 3) << "</td><td>" << Optional(tree.dbh, 3)
       << "</td><td>" << (tree.branches ? std::to_string(*tree.branches) : "") << "</td><td>"
       << Fixed(tree.status.seconds, 1) << "</td><td><a href='logs/" << HtmlEscape(tree.name)
       << ".log'>log</a></td></tr>\n";
  return html.str();
}

std::string Counts(const std::vector<TreeSummary>& trees) {
  std::map<std::string, int> counts;
  for (const TreeSummary& tree : trees) ++counts[tree.status.status];
  std::string text;
  for (const auto& [status, count] : counts) {
    text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + status;
  }
  return text;
}

const char kStyle[] =
    "body{font-family:sans-serif;margin:2em;color:#222}"
    "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 6px;"
    "text-align:right;vertical-align:middle}td:nth-child(2),td:nth-child(3),td:nth-child(4),"
    "td.error{text-align:left}td.error{max-width:28em;font-size:90%}"
    "tr.failed,tr.crashed{background:#fde0dc}tr.interrupted,tr.running,tr.not-run"
    "{background:#fff6d5}.legend span{display:inline-block;width:12px;height:12px;"
    "margin:0 4px 0 12px;vertical-align:middle}";

}  // namespace

std::string SummaryHtml(const std::vector<TreeSummary>& trees, const Manifest& manifest) {
  const std::time_t now = std::time(nullptr);
  char written[64];
  std::strftime(written, sizeof(written), "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>sylva batch: " << trees.size()
       << " trees</title><style>" << kStyle << "</style></head><body>\n"
       << "<h1>sylva batch</h1>\n<p>" << trees.size() << " trees of "
       << HtmlEscape(manifest.path.string()) << ": " << HtmlEscape(Counts(trees)) << ". Written "
       << written << "; the same figures are in <a href='summary.csv'>summary.csv</a>.</p>\n"
       << Plots(trees) << "\n<h2>Trees</h2>\n<table><tr><th>preview</th><th>name</th>"
       << "<th>status</th><th>stage</th><th>error</th><th>IoU input mean</th><th>min</th>"
       << "<th>IoU held-out mean</th><th>min</th><th>height</th><th>crown width</th>"
       << "<th>crown volume (hull)</th><th>DBH</th><th>branches</th><th>seconds</th>"
       << "<th>log</th></tr>\n";
  for (const TreeSummary& tree : trees) html << TreeRow(tree);
  html << "</table>\n</body></html>\n";
  return html.str();
}

}  // namespace sylva
