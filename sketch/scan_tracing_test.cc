#include "sketch/scan_tracing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "sketch/scan_skeleton.h"

namespace sylva {
namespace {

constexpr int kLineWidthPx = 5;  // as TreeSketchNet's authors draw
// What the tracer measures for it: antialiased, its half-covered fringe
// pixels count as ink, so it binarises 6 to 7 px wide.
constexpr double kTracedWidthPx = 6.0;

// A white page of `width` x `height` pixels to draw black lines on.
cv::Mat Page(int width, int height) { return cv::Mat(height, width, CV_8U, cv::Scalar(255)); }

void Line(cv::Mat& page, cv::Point a, cv::Point b, int width = kLineWidthPx) {
  cv::line(page, a, b, cv::Scalar(0), width, cv::LINE_AA);
}

FloatImage ToFloat(const cv::Mat& page) {
  FloatImage grey(page.cols, page.rows, 1);
  for (int y = 0; y < page.rows; ++y) {
    for (int x = 0; x < page.cols; ++x) grey.at(x, y) = page.at<uchar>(y, x) / 255.0f;
  }
  return grey;
}

// Distance from p to the stroke's polyline.
double DistanceToStroke(const Eigen::Vector2d& p, const SketchStroke& stroke) {
  double best = 1e300;
  const size_t n = stroke.points.size();
  for (size_t i = 0; i + 1 < n + (stroke.closed ? 1 : 0); ++i) {
    const Eigen::Vector2d a = stroke.points[i], b = stroke.points[(i + 1) % n];
    const Eigen::Vector2d ab = b - a;
    const double t =
        ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

// The largest distance from points along a-b to the nearest stroke of `role`.
double WorstCoverage(const SketchDrawing& drawing, cv::Point a, cv::Point b, StrokeRole role) {
  double worst = 0;
  for (double t = 0.05; t <= 0.95; t += 0.05) {
    const Eigen::Vector2d p(a.x + 0.5 + t * (b.x - a.x), a.y + 0.5 + t * (b.y - a.y));
    double best = 1e300;
    for (const SketchStroke& s : drawing.strokes) {
      if (s.role == role) best = std::min(best, DistanceToStroke(p, s));
    }
    worst = std::max(worst, best);
  }
  return worst;
}

const SketchStroke* FindClosedCrown(const SketchDrawing& drawing) {
  for (const SketchStroke& s : drawing.strokes) {
    if (s.role == StrokeRole::kCrown && s.closed) return &s;
  }
  return nullptr;
}

// Trunk (400, 750) -> (400, 500), two branches up from there, and an
// elliptic crown above them that they do not touch.
TEST(ScanTracingTest, YTreeUnderACrown) {
  cv::Mat page = Page(800, 800);
  const cv::Point base(400, 750), fork(400, 500), left(320, 430), right(480, 430);
  Line(page, base, fork);
  Line(page, fork, left);
  Line(page, fork, right);
  cv::ellipse(page, cv::Point(400, 260), cv::Size(200, 150), 0, 0, 360, cv::Scalar(0), kLineWidthPx,
              cv::LINE_AA);
  ScanTracingSummary summary;
  const SketchDrawing drawing =
      TraceScannedDrawing(ToFloat(page), "y_tree", ScanTracingOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  drawing.Check();
  EXPECT_EQ(summary.junctions, 1);
  EXPECT_EQ(summary.end_points, 3);
  EXPECT_EQ(drawing.CountRole(StrokeRole::kBranch), 3);
  ASSERT_EQ(drawing.CountRole(StrokeRole::kCrown), 1);
  EXPECT_NEAR(summary.line_width_px, kTracedWidthPx, 1.5);
  for (const auto& [a, b] : {std::pair{base, fork}, {fork, left}, {fork, right}}) {
    EXPECT_LT(WorstCoverage(drawing, a, b, StrokeRole::kBranch), 3.0);
  }
  const SketchStroke* crown = FindClosedCrown(drawing);
  ASSERT_NE(crown, nullptr);
  for (double angle = 0; angle < 2 * M_PI; angle += 0.1) {
    const Eigen::Vector2d p(400.5 + 200 * std::cos(angle), 260.5 + 150 * std::sin(angle));
    EXPECT_LT(DistanceToStroke(p, *crown), 3.0) << "at angle " << angle;
  }
  for (const SketchStroke& s : drawing.strokes) EXPECT_NEAR(s.width, kTracedWidthPx, 1.5);
  ASSERT_TRUE(drawing.root.has_value());
  EXPECT_LT((*drawing.root - Eigen::Vector2d(400.5, 750.5)).norm(), 4.0);
}

// Branches that reach into the crown cross its outline: the outline is
// split at the crossings but still chains into one closed crown stroke.
TEST(ScanTracingTest, BranchesCrossingTheCrownOutline) {
  cv::Mat page = Page(800, 800);
  Line(page, {400, 750}, {400, 560});
  Line(page, {400, 560}, {300, 250});
  Line(page, {400, 560}, {500, 250});
  cv::ellipse(page, cv::Point(400, 300), cv::Size(220, 180), 0, 0, 360, cv::Scalar(0), kLineWidthPx,
              cv::LINE_AA);
  ScanTracingSummary summary;
  const SketchDrawing drawing =
      TraceScannedDrawing(ToFloat(page), "crossing", ScanTracingOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  drawing.Check();
  EXPECT_EQ(summary.closed_crowns, 1);
  EXPECT_EQ(summary.crown_strokes, 1);
  EXPECT_EQ(summary.junctions, 3);  // the fork and two crossings
  EXPECT_LT(WorstCoverage(drawing, {400, 750}, {400, 560}, StrokeRole::kBranch), 3.0);
  EXPECT_LT(WorstCoverage(drawing, {400, 560}, {300, 250}, StrokeRole::kBranch), 3.0);
  EXPECT_LT(WorstCoverage(drawing, {400, 560}, {500, 250}, StrokeRole::kBranch), 3.0);
}

// A trunk drawn as two outlines 40 px apart (centre to centre), 600 px long, open or
// closed at the bottom, becomes one branch along their middle, 40 px wide.
void ExpectOneTrunk(bool closed_bottom) {
  cv::Mat page = Page(600, 800);
  Line(page, {280, 750}, {280, 150});
  Line(page, {320, 750}, {320, 150});
  if (closed_bottom) Line(page, {280, 750}, {320, 750});
  ScanTracingSummary summary;
  const SketchDrawing drawing =
      TraceScannedDrawing(ToFloat(page), "outlined_trunk", ScanTracingOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.trunk_pairs, 1);
  ASSERT_EQ(drawing.strokes.size(), 1u);
  const SketchStroke& trunk = drawing.strokes[0];
  EXPECT_EQ(trunk.role, StrokeRole::kBranch);
  EXPECT_NEAR(trunk.width, 40.0, 0.2 * 40.0);
  double top = 1e300, bottom = -1e300;
  for (const Eigen::Vector2d& p : trunk.points) {
    EXPECT_NEAR(p.x(), 300.5, 3.0);
    top = std::min(top, p.y());
    bottom = std::max(bottom, p.y());
  }
  EXPECT_LT(top, 150 + 0.1 * 600);
  EXPECT_GT(bottom, 750 - 0.1 * 600);
}

TEST(ScanTracingTest, TrunkDrawnAsTwoParallelOutlines) { ExpectOneTrunk(false); }
TEST(ScanTracingTest, TrunkDrawnAsTwoOutlinesClosedAtTheBottom) { ExpectOneTrunk(true); }

// A line with a small skip is one stroke; a spur from a brush blob goes.
TEST(ScanTracingTest, ClosesGapsAndPrunesSpurs) {
  cv::Mat page = Page(600, 300);
  Line(page, {50, 150}, {280, 150});
  Line(page, {290, 150}, {550, 150});
  Line(page, {400, 150}, {404, 142});  // a 9 px spur
  ScanTracingSummary summary;
  const SketchDrawing drawing =
      TraceScannedDrawing(ToFloat(page), "gap", ScanTracingOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.gaps_closed, 1);
  EXPECT_EQ(summary.spurs_pruned, 1);
  ASSERT_EQ(drawing.strokes.size(), 1u);
  EXPECT_LT(WorstCoverage(drawing, {50, 150}, {550, 150}, StrokeRole::kBranch), 2.0);
}

// Uneven light: a page darkening to the right keeps its line and only it.
TEST(ScanTracingTest, SauvolaIgnoresShading) {
  cv::Mat page = Page(600, 400);
  for (int x = 0; x < page.cols; ++x) page.col(x).setTo(255 - x * 120 / page.cols);
  Line(page, {50, 200}, {550, 200});
  ScanTracingSummary summary;
  const SketchDrawing drawing =
      TraceScannedDrawing(ToFloat(page), "shaded", ScanTracingOptions(), &summary);
  ASSERT_EQ(drawing.strokes.size(), 1u) << summary.BriefReport();
  EXPECT_LT(WorstCoverage(drawing, {50, 200}, {550, 200}, StrokeRole::kBranch), 2.0);
}

TEST(ScanTracingTest, BlankPageIsAnInputError) {
  const cv::Mat page = Page(300, 200);
  try {
    TraceScannedDrawing(ToFloat(page), "blank.png", ScanTracingOptions());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "blank.png");
    EXPECT_NE(std::string(e.what()).find("blank page"), std::string::npos) << e.what();
  }
}

TEST(ScanTracingTest, CorruptImageIsAnInputErrorNamingTheFile) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "sylva_scan_tracing_corrupt.png";
  {
    std::ofstream out(path, std::ios::binary);
    out << "\x89PNG\r\n\x1a\n not really a png";
  }
  try {
    TraceScannedDrawing(path, ScanTracingOptions());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(ScanTracingTest, OptionsCheckNamesTheOption) {
  ScanTracingOptions options;
  options.sauvola_k = -1;
  try {
    options.Check();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "ScanTracing.sauvola_k");
  }
  EXPECT_NO_THROW(ScanTracingOptions().Check());
}

// A real hand sketch (TreeSketchNet, BSD-3-Clause; see the folder's
// PROVENANCE.md): a closed crown outline with branches inside, and a trunk
// drawn as two outlines.
TEST(ScanTracingTest, RealTreeSketchNetSketch) {
  const std::filesystem::path path = std::filesystem::path(SYLVA_SOURCE_DIR) /
                                     "datasets/sketches/treesketchnet/2_camera_right.png";
  ScanTracingSummary summary;
  const SketchDrawing drawing = TraceScannedDrawing(path, ScanTracingOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NO_THROW(drawing.Check());
  EXPECT_EQ(drawing.width, 608);
  EXPECT_GE(summary.closed_crowns, 1);
  EXPECT_GE(drawing.CountRole(StrokeRole::kBranch), 20);
  EXPECT_GE(summary.trunk_pairs, 1);
  EXPECT_NEAR(summary.line_width_px, 5, 2);
  // The trunk's two outlines meet the page's bottom edge at x = 310 and 323.
  ASSERT_TRUE(drawing.root.has_value());
  EXPECT_NEAR(drawing.root->x(), 317, 5);
  EXPECT_GT(drawing.root->y(), 590);
  // The crown encloses most of the drawing.
  const SketchStroke* crown = FindClosedCrown(drawing);
  ASSERT_NE(crown, nullptr);
  std::vector<cv::Point2f> polygon;
  for (const Eigen::Vector2d& p : crown->points) polygon.emplace_back(p.x(), p.y());
  EXPECT_GT(std::abs(cv::contourArea(polygon)), 0.3 * 608 * 608);
}

// sylva binarises and thins drawings itself (scan_skeleton.h) instead of
// linking OpenCV's contrib module: the same ink and skeleton, pixel for
// pixel, as cv::ximgproc's Sauvola and Zhang-Suen, on the real sketch, on
// a photo of a tree and on noisy pages (random grey, with strokes), at the
// tracer's window and others.
TEST(ScanTracingTest, SauvolaAndThinningAreOpenCvContribs) {
  std::vector<cv::Mat> pages;
  for (const char* file : {"datasets/sketches/treesketchnet/2_camera_right.png",
                           "datasets/tuxpaint-trees/birch.png"}) {
    const FloatImage image = ReadImage(std::filesystem::path(SYLVA_SOURCE_DIR) / file);
    cv::Mat grey(image.height(), image.width(), CV_8U);
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) {
        grey.at<uchar>(y, x) = cv::saturate_cast<uchar>(255.0f * image.at(x, y, 0));
      }
    }
    pages.push_back(grey);
  }
  RandomEngine random(7);
  const auto pick = [&](int lo, int hi) {
    return lo + static_cast<int>(random.UniformInt(hi - lo + 1));
  };
  for (int k = 0; k < 3; ++k) {
    cv::Mat page(181 + 40 * k, 233, CV_8U);
    for (int y = 0; y < page.rows; ++y) {
      for (int x = 0; x < page.cols; ++x) {
        page.at<uchar>(y, x) = static_cast<uchar>(pick(k == 0 ? 0 : 150, 255));
      }
    }
    for (int line = 0; line < 12; ++line) {
      const cv::Point a(pick(0, page.cols - 1), pick(0, page.rows - 1));
      const cv::Point b(pick(0, page.cols - 1), pick(0, page.rows - 1));
      Line(page, a, b, pick(1, 9));
    }
    pages.push_back(page);
  }
  int64_t ink_pixels = 0, skeleton_pixels = 0;
  for (const cv::Mat& page : pages) {
    for (const int window : {15, 31, 61}) {
      for (const double k : {0.1, 0.34}) {
        cv::Mat expected;
        cv::ximgproc::niBlackThreshold(page, expected, 255, cv::THRESH_BINARY_INV, window, k,
                                       cv::ximgproc::BINARIZATION_SAUVOLA, 128.0);
        const cv::Mat ink = scan::SauvolaInk(page, window, k, 128.0);
        ASSERT_EQ(cv::countNonZero(ink != expected), 0) << page.size() << " window " << window;
        ink_pixels += cv::countNonZero(ink);
        cv::Mat thinned;
        cv::ximgproc::thinning(ink, thinned, cv::ximgproc::THINNING_ZHANGSUEN);
        const cv::Mat skeleton = scan::ThinZhangSuen(ink);
        ASSERT_EQ(cv::countNonZero(skeleton != thinned), 0) << page.size() << " window " << window;
        skeleton_pixels += cv::countNonZero(skeleton);
      }
    }
  }
  EXPECT_GT(ink_pixels, 100000);
  EXPECT_GT(skeleton_pixels, 10000);
}

}  // namespace
}  // namespace sylva
