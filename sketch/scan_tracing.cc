#include "sketch/scan_tracing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "sketch/scan_interpret.h"
#include "sketch/scan_skeleton.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int kMinSauvolaWindowPx = 15;
// Junction pixels this close are one junction whatever the line width (a
// diagonal step of a one-pixel line is 1.4 px).
constexpr double kMinJunctionClusterPx = 2.0;
// Sauvola's dynamic range of the standard deviation for 8-bit grey.
constexpr double kSauvolaRange = 128.0;

class StepTimer {
 public:
  // Seconds since the last call (or construction).
  double Lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

cv::Mat ToGrey8(const FloatImage& grey) {
  cv::Mat image(grey.height(), grey.width(), CV_8U);
  for (int y = 0; y < grey.height(); ++y) {
    uchar* row = image.ptr<uchar>(y);
    for (int x = 0; x < grey.width(); ++x) {
      row[x] = cv::saturate_cast<uchar>(std::lround(255.0f * grey.at(x, y)));
    }
  }
  return image;
}

// Grey of a photo: the mean of its colour channels, composited over white
// paper by its alpha.
FloatImage GreyOf(const FloatImage& image, int alpha_channel) {
  FloatImage grey(image.width(), image.height(), 1);
  const int colours = alpha_channel >= 0 ? image.channels() - 1 : image.channels();
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      float sum = 0;
      for (int c = 0, used = 0; used < colours; ++c) {
        if (c == alpha_channel) continue;
        sum += image.at(x, y, c);
        ++used;
      }
      const float alpha = alpha_channel >= 0 ? image.at(x, y, alpha_channel) : 1.0f;
      grey.at(x, y) = alpha * sum / colours + (1 - alpha);
    }
  }
  return grey;
}

// A page without ink: nothing darker than the paper by min_ink_contrast.
void CheckNotBlank(const cv::Mat& grey, const ScanTracingOptions& options,
                   const std::string& source) {
  int histogram[256] = {0};
  for (int y = 0; y < grey.rows; ++y) {
    for (int x = 0; x < grey.cols; ++x) ++histogram[grey.at<uchar>(y, x)];
  }
  int darkest = 0, median = 0;
  while (histogram[darkest] == 0) ++darkest;
  for (int seen = 0; seen + histogram[median] <= static_cast<int>(grey.total()) / 2; ++median) {
    seen += histogram[median];
  }
  SYLVA_CHECK_INPUT(median - darkest >= options.min_ink_contrast * 255, source)
      << "blank page: nothing is darker than the paper (grey " << median / 255.0
      << ") by ScanTracing.min_ink_contrast = " << options.min_ink_contrast;
}

cv::Mat Binarise(const cv::Mat& grey, const ScanTracingOptions& options) {
  const int shorter = std::min(grey.rows, grey.cols);
  int window = static_cast<int>(std::lround(options.sauvola_window_fraction * shorter)) | 1;
  window = std::max(window, kMinSauvolaWindowPx);
  return scan::SauvolaInk(grey, window, options.sauvola_k, kSauvolaRange);
}

// Line width 2 d - 1 from the median distance d (pixels to the paper) over
// `pixels`: a line w pixels wide has its centre (w + 1) / 2 from the paper.
double WidthFromDistances(std::vector<float> distances) {
  if (distances.empty()) return 1.0;
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  return std::max(1.0, 2.0 * distances[distances.size() / 2] - 1.0);
}

double MedianLineWidth(const cv::Mat& skeleton, const cv::Mat& distance) {
  std::vector<float> distances;
  for (int y = 0; y < skeleton.rows; ++y) {
    for (int x = 0; x < skeleton.cols; ++x) {
      if (skeleton.at<uchar>(y, x)) distances.push_back(distance.at<float>(y, x));
    }
  }
  return WidthFromDistances(std::move(distances));
}

// Drops ink blobs smaller than `min_area_px` (dust, dots) from the ink and
// its skeleton.
void RemoveSpecks(double min_area_px, cv::Mat& ink, cv::Mat& skeleton) {
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(ink, labels, stats, centroids, 8);
  std::vector<bool> speck(count, false);
  for (int c = 1; c < count; ++c) speck[c] = stats.at<int>(c, cv::CC_STAT_AREA) < min_area_px;
  for (int y = 0; y < ink.rows; ++y) {
    for (int x = 0; x < ink.cols; ++x) {
      if (speck[labels.at<int>(y, x)]) ink.at<uchar>(y, x) = skeleton.at<uchar>(y, x) = 0;
    }
  }
}

// The width of an edge's line, away from its junctions (where the distance
// transform sees the other strokes' ink too).
double EdgeWidth(const scan::SkeletonEdge& edge, const scan::SkeletonGraph& graph,
                 const cv::Mat& distance, double line_width) {
  const auto near_junction = [&](const Eigen::Vector2d& p) {
    for (int node : {edge.node_a, edge.node_b}) {
      if (node >= 0 && graph.nodes[node].junction &&
          (p - graph.nodes[node].position).norm() < 1.5 * line_width) {
        return true;
      }
    }
    return false;
  };
  std::vector<float> distances, all;
  for (const Eigen::Vector2d& p : edge.points) {
    const int x = std::clamp(static_cast<int>(std::lround(p.x())), 0, distance.cols - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.y())), 0, distance.rows - 1);
    all.push_back(distance.at<float>(y, x));
    if (!near_junction(p)) distances.push_back(all.back());
  }
  return WidthFromDistances(distances.empty() ? all : distances);
}

std::vector<Eigen::Vector2d> Simplify(const std::vector<Eigen::Vector2d>& points, bool closed,
                                      double tolerance_px) {
  std::vector<cv::Point2f> in, out;  // approxPolyDP takes no doubles
  for (const Eigen::Vector2d& p : points) in.emplace_back(p.x(), p.y());
  cv::approxPolyDP(in, out, tolerance_px, closed);
  if (out.size() < (closed ? 3u : 2u)) return points;
  std::vector<Eigen::Vector2d> simplified;
  for (const cv::Point2f& p : out) simplified.emplace_back(p.x, p.y);
  return simplified;
}

// The tree's base: the lowest end of a trunk drawn as two outlines if there
// is one (the scraps of its bottom cap are lower but no trunk), else of any
// branch stroke. Pixel coordinates.
std::optional<Eigen::Vector2d> Root(const std::vector<scan::TracedStroke>& traced) {
  const bool has_trunk = std::any_of(traced.begin(), traced.end(),
                                     [](const scan::TracedStroke& t) { return t.trunk_pair; });
  std::optional<Eigen::Vector2d> root;
  for (const scan::TracedStroke& t : traced) {
    if (t.role != StrokeRole::kBranch || t.edge.points.empty() || (has_trunk && !t.trunk_pair)) {
      continue;
    }
    for (const Eigen::Vector2d& end : {t.edge.points.front(), t.edge.points.back()}) {
      if (!root || end.y() > root->y()) root = end;
    }
  }
  return root;
}

// Traced strokes -> the drawing: simplified, in canvas coordinates (pixel
// centres at +0.5).
SketchDrawing ToDrawing(const std::vector<scan::TracedStroke>& traced, const cv::Size& size,
                        const std::string& source, double tolerance_px) {
  SketchDrawing drawing;
  drawing.source = source;
  drawing.width = size.width;
  drawing.height = size.height;
  const Eigen::Vector2d to_canvas(0.5, 0.5);
  for (const scan::TracedStroke& t : traced) {
    if (t.edge.points.size() < (t.edge.closed ? 3u : 2u)) continue;
    SketchStroke stroke;
    for (const Eigen::Vector2d& p : Simplify(t.edge.points, t.edge.closed, tolerance_px)) {
      stroke.points.push_back(p + to_canvas);
    }
    stroke.role = t.role;
    stroke.closed = t.edge.closed;
    stroke.width = t.width;
    drawing.strokes.push_back(std::move(stroke));
  }
  if (const std::optional<Eigen::Vector2d> root = Root(traced)) drawing.root = *root + to_canvas;
  return drawing;
}

void CountNodes(const scan::SkeletonGraph& graph, ScanTracingSummary& summary) {
  for (int degree : graph.Degrees()) {
    summary.junctions += degree >= 3;
    summary.end_points += degree == 1;
  }
}

void CountRoles(const SketchDrawing& drawing, ScanTracingSummary& summary) {
  summary.crown_strokes = drawing.CountRole(StrokeRole::kCrown);
  summary.branch_strokes = drawing.CountRole(StrokeRole::kBranch);
  for (const SketchStroke& s : drawing.strokes) {
    summary.closed_crowns += s.role == StrokeRole::kCrown && s.closed;
  }
}

// Steps 3 and 4: the cleaned graph of the skeleton, as strokes with widths.
std::vector<scan::TracedStroke> TraceStrokes(const cv::Mat& skeleton, const cv::Mat& distance,
                                             const ScanTracingOptions& options,
                                             ScanTracingSummary& summary) {
  const double w = summary.line_width_px;
  const double cluster_px = std::max(kMinJunctionClusterPx, options.junction_cluster_widths * w);
  scan::SkeletonGraph graph = scan::TraceSkeleton(skeleton, cluster_px);
  scan::MergeThroughTwoWayNodes(graph);
  summary.spurs_pruned = scan::PruneSpurs(options.spur_length_widths * w, graph);
  summary.gaps_closed =
      scan::CloseGaps(options.gap_length_widths * w, options.gap_max_angle_deg * kDegree, graph);
  CountNodes(graph, summary);
  std::vector<scan::TracedStroke> strokes;
  for (const scan::SkeletonEdge& edge : graph.edges) {
    strokes.push_back({edge, EdgeWidth(edge, graph, distance, w)});
  }
  return strokes;
}

// Steps 5 and 6.
void Interpret(const cv::Mat& ink, const ScanTracingOptions& options, ScanTracingSummary& summary,
               std::vector<scan::TracedStroke>& strokes) {
  const double w = summary.line_width_px;
  const cv::Rect box = cv::boundingRect(ink);
  scan::TrunkPairOptions trunk;
  trunk.line_width_px = w;
  trunk.min_separation_px = options.trunk_min_separation_widths * w;
  trunk.max_separation_px =
      std::max(trunk.min_separation_px,
               options.trunk_max_separation_fraction * std::max(box.width, box.height));
  trunk.max_angle_rad = options.trunk_max_angle_deg * kDegree;
  trunk.min_length_separations = options.trunk_min_length_separations;
  trunk.min_base_y_px = box.y + box.height * (1 - options.trunk_max_base_height_fraction);
  summary.trunk_pairs = scan::MergeTrunkPairs(ink, trunk, strokes);
  scan::CrownOptions crown;
  crown.line_width_px = w;
  crown.min_area_fraction = options.crown_min_area_fraction;
  crown.on_outline_fraction = options.crown_on_outline_fraction;
  scan::MarkCrownStrokes(ink, crown, strokes);
}

}  // namespace

void ScanTracingOptions::Check() const {
  const auto in_range = [](double value, double low, double high) {
    return std::isfinite(value) && value >= low && value <= high;
  };
  SYLVA_CHECK_INPUT(in_range(sauvola_window_fraction, 1e-3, 1),
                    "ScanTracing.sauvola_window_fraction")
      << "must be in [0.001, 1] of the shorter image side, got " << sauvola_window_fraction;
  SYLVA_CHECK_INPUT(in_range(sauvola_k, 1e-3, 1), "ScanTracing.sauvola_k")
      << "must be in [0.001, 1], got " << sauvola_k;
  SYLVA_CHECK_INPUT(in_range(min_ink_contrast, 0, 1), "ScanTracing.min_ink_contrast")
      << "must be a grey difference in [0, 1], got " << min_ink_contrast;
  SYLVA_CHECK_INPUT(in_range(junction_cluster_widths, 0, 100),
                    "ScanTracing.junction_cluster_widths")
      << "must be in [0, 100] line widths, got " << junction_cluster_widths;
  SYLVA_CHECK_INPUT(in_range(simplify_tolerance_px, 0, 100), "ScanTracing.simplify_tolerance_px")
      << "must be in [0, 100] pixels, got " << simplify_tolerance_px;
  SYLVA_CHECK_INPUT(in_range(spur_length_widths, 0, 1e3), "ScanTracing.spur_length_widths")
      << "must be in [0, 1000] line widths, got " << spur_length_widths;
  SYLVA_CHECK_INPUT(in_range(gap_length_widths, 0, 1e3), "ScanTracing.gap_length_widths")
      << "must be in [0, 1000] line widths, got " << gap_length_widths;
  SYLVA_CHECK_INPUT(in_range(gap_max_angle_deg, 0, 90), "ScanTracing.gap_max_angle_deg")
      << "must be in [0, 90] degrees, got " << gap_max_angle_deg;
  SYLVA_CHECK_INPUT(in_range(trunk_min_separation_widths, 1, 1e3),
                    "ScanTracing.trunk_min_separation_widths")
      << "must be in [1, 1000] line widths, got " << trunk_min_separation_widths;
  SYLVA_CHECK_INPUT(in_range(trunk_max_separation_fraction, 0, 1),
                    "ScanTracing.trunk_max_separation_fraction")
      << "must be in [0, 1] of the drawing's size, got " << trunk_max_separation_fraction;
  SYLVA_CHECK_INPUT(in_range(trunk_max_angle_deg, 0, 90), "ScanTracing.trunk_max_angle_deg")
      << "must be in [0, 90] degrees, got " << trunk_max_angle_deg;
  SYLVA_CHECK_INPUT(in_range(trunk_min_length_separations, 0, 1e3),
                    "ScanTracing.trunk_min_length_separations")
      << "must be in [0, 1000] separations, got " << trunk_min_length_separations;
  SYLVA_CHECK_INPUT(in_range(trunk_max_base_height_fraction, 0, 1),
                    "ScanTracing.trunk_max_base_height_fraction")
      << "must be in [0, 1] of the drawing's height, got " << trunk_max_base_height_fraction;
  SYLVA_CHECK_INPUT(in_range(crown_min_area_fraction, 0, 1), "ScanTracing.crown_min_area_fraction")
      << "must be in [0, 1] of the ink's bounding box, got " << crown_min_area_fraction;
  SYLVA_CHECK_INPUT(in_range(crown_on_outline_fraction, 0, 1),
                    "ScanTracing.crown_on_outline_fraction")
      << "must be in [0, 1], got " << crown_on_outline_fraction;
}

std::string ScanTracingSummary::BriefReport() const {
  std::ostringstream out;
  out << width_px << " x " << height_px << " px, ink " << 100 * ink_fraction << " %, line width "
      << line_width_px << " px: " << junctions << " junctions, " << end_points << " ends, "
      << spurs_pruned << " spurs pruned, " << gaps_closed << " gaps closed, " << trunk_pairs
      << " trunk pairs; " << branch_strokes << " branch strokes, " << crown_strokes
      << " crown strokes (" << closed_crowns << " closed); "
      << binarise_s + thin_s + trace_s + interpret_s << " s (binarise " << binarise_s << ", thin "
      << thin_s << ", trace " << trace_s << ", interpret " << interpret_s << ")";
  return out.str();
}

SketchDrawing TraceScannedDrawing(const FloatImage& grey, const std::string& source,
                                  const ScanTracingOptions& options,
                                  ScanTracingSummary* summary_out) {
  options.Check();
  SYLVA_CHECK_INPUT(!grey.empty() && grey.channels() == 1, source)
      << "expected a non-empty grey image, got " << grey.width() << " x " << grey.height()
      << " with " << grey.channels() << " channels";
  ScanTracingSummary summary;
  summary.width_px = grey.width();
  summary.height_px = grey.height();
  StepTimer timer;
  const cv::Mat grey8 = ToGrey8(grey);
  CheckNotBlank(grey8, options, source);
  cv::Mat ink = Binarise(grey8, options);
  summary.binarise_s = timer.Lap();

  cv::Mat skeleton = scan::ThinZhangSuen(ink);
  cv::Mat distance;
  cv::distanceTransform(ink, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  summary.line_width_px = MedianLineWidth(skeleton, distance);
  const double w = summary.line_width_px;
  RemoveSpecks(options.spur_length_widths * w * w, ink, skeleton);
  summary.ink_fraction = cv::countNonZero(ink) / static_cast<double>(ink.total());
  SYLVA_CHECK_INPUT(summary.ink_fraction > 0, source)
      << "blank page: no line longer than ScanTracing.spur_length_widths = "
      << options.spur_length_widths << " line widths";
  summary.thin_s = timer.Lap();

  std::vector<scan::TracedStroke> strokes = TraceStrokes(skeleton, distance, options, summary);
  summary.trace_s = timer.Lap();
  Interpret(ink, options, summary, strokes);
  SketchDrawing drawing = ToDrawing(strokes, ink.size(), source, options.simplify_tolerance_px);
  summary.interpret_s = timer.Lap();
  CountRoles(drawing, summary);
  drawing.Check();
  if (summary_out) *summary_out = summary;
  return drawing;
}

SketchDrawing TraceScannedDrawing(const std::filesystem::path& image,
                                  const ScanTracingOptions& options, ScanTracingSummary* summary) {
  options.Check();
  const ImageHeader header = ReadImageHeader(image);
  const FloatImage pixels = ReadImage(image);
  return TraceScannedDrawing(GreyOf(pixels, header.alpha_channel), image.string(), options,
                             summary);
}

}  // namespace sylva
