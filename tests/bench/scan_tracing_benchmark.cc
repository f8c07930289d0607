// Benchmark of scanned-drawing tracing (sketch/scan_tracing.h, issue 14:
// "a 4-megapixel page in well under 2 s"): the TreeSketchNet maple sketch
// scaled up to a 2000 x 2000 page (lines about 16 px wide, as a 300 dpi scan
// of a felt-pen drawing would have), traced whole; its steps' times; and the
// thinning step beside a simple reference run in the same process on the
// same ink: OpenCV's cv::ximgproc::thinning (Zhang & Suen), which visits
// every pixel of the page in each of its sub-iterations, where ours visits
// only the ink's current boundary. Both implement the same rule, so the two
// skeletons must agree pixel for pixel (tolerance: 0.1 % of the skeleton),
// and their traced graphs must have the same junctions and edges; the
// program fails otherwise.
//
// usage: sylva_scan_tracing_benchmark [--quick]   (--quick: a 1216 px page)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>

#include "sketch/scan_skeleton.h"
#include "sketch/scan_tracing.h"
#include "tests/bench/agreement.h"

namespace sylva {
namespace {

constexpr int kRepeats = 3;  // the fastest of these runs is reported

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

cv::Mat LoadPage(int side_px) {
  const std::filesystem::path path = std::filesystem::path(SYLVA_SOURCE_DIR) /
                                     "datasets/sketches/treesketchnet/2_camera_right.png";
  const cv::Mat sketch = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  if (sketch.empty()) throw std::runtime_error("cannot read " + path.string());
  cv::Mat page;
  cv::resize(sketch, page, cv::Size(side_px, side_px), 0, 0, cv::INTER_LINEAR);
  return page;
}

FloatImage ToFloat(const cv::Mat& page) {
  FloatImage grey(page.cols, page.rows, 1);
  for (int y = 0; y < page.rows; ++y) {
    for (int x = 0; x < page.cols; ++x) grey.at(x, y) = page.at<uchar>(y, x) / 255.0f;
  }
  return grey;
}

// The whole tracing, fastest of kRepeats.
ScanTracingSummary TimeTracing(const cv::Mat& page) {
  const FloatImage grey = ToFloat(page);
  ScanTracingSummary best;
  double best_s = 1e300;
  for (int r = 0; r < kRepeats; ++r) {
    ScanTracingSummary summary;
    const auto start = std::chrono::steady_clock::now();
    TraceScannedDrawing(grey, "page", ScanTracingOptions(), &summary);
    const double seconds = Seconds(start);
    if (seconds < best_s) best_s = seconds, best = summary;
  }
  std::printf("  traced in %.3f s (%.2f s per 4 MP): %s\n", best_s,
              best_s * 4e6 / static_cast<double>(page.total()), best.BriefReport().c_str());
  return best;
}

// The ink as TraceScannedDrawing binarises it with the default options.
cv::Mat Ink(const cv::Mat& page) {
  const ScanTracingOptions options;
  const int window =
      std::max(15, static_cast<int>(std::lround(options.sauvola_window_fraction * page.rows)) | 1);
  cv::Mat ink;
  cv::ximgproc::niBlackThreshold(page, ink, 255, cv::THRESH_BINARY_INV, window, options.sauvola_k,
                                 cv::ximgproc::BINARIZATION_SAUVOLA, 128);
  return ink;
}

template <typename Thin>
cv::Mat TimeThinning(const char* name, const cv::Mat& ink, Thin thin, double* best_s) {
  cv::Mat skeleton;
  *best_s = 1e300;
  for (int r = 0; r < kRepeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    skeleton = thin(ink);
    *best_s = std::min(*best_s, Seconds(start));
  }
  std::printf("  thinning, %-40s %.3f s\n", name, *best_s);
  return skeleton;
}

void CompareGraphs(const cv::Mat& fast, const cv::Mat& reference, Agreement* agreement) {
  const scan::SkeletonGraph a = scan::TraceSkeleton(fast, 3.0);
  const scan::SkeletonGraph b = scan::TraceSkeleton(reference, 3.0);
  const auto junctions = [](const scan::SkeletonGraph& g) {
    return std::count_if(g.nodes.begin(), g.nodes.end(), [](const auto& n) { return n.junction; });
  };
  std::printf("  graphs: %zu / %zu edges, %ld / %ld junctions (ours / reference)\n", a.edges.size(),
              b.edges.size(), junctions(a), junctions(b));
  agreement->AtMost("edge count difference", std::abs(double(a.edges.size()) - b.edges.size()), 0);
  agreement->AtMost("junction count difference", std::abs(double(junctions(a) - junctions(b))), 0);
}

void RunPage(int side_px, Agreement* agreement) {
  std::printf("page %d x %d px (%.1f MP)\n", side_px, side_px, side_px * side_px / 1e6);
  const cv::Mat page = LoadPage(side_px);
  TimeTracing(page);
  const cv::Mat ink = Ink(page);
  double ours_s = 0, reference_s = 0;
  const cv::Mat ours = TimeThinning(
      "ours (boundary list):", ink, [](const cv::Mat& m) { return scan::ThinZhangSuen(m); },
      &ours_s);
  const cv::Mat reference = TimeThinning(
      "reference (cv::ximgproc::thinning):", ink,
      [](const cv::Mat& m) {
        cv::Mat out;
        cv::ximgproc::thinning(m, out, cv::ximgproc::THINNING_ZHANGSUEN);
        return out;
      },
      &reference_s);
  std::printf("  thinning speed-up: %.1fx\n", reference_s / ours_s);
  cv::Mat differ;
  cv::bitwise_xor(ours != 0, reference != 0, differ);
  const double skeleton_px = std::max(1, cv::countNonZero(reference));
  agreement->AtMost("skeleton pixels differing (share)", cv::countNonZero(differ) / skeleton_px,
                    1e-3);
  CompareGraphs(ours, reference, agreement);
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  try {
    sylva::Agreement agreement("cv::ximgproc::thinning");
    sylva::RunPage(quick ? 1216 : 2000, &agreement);
    return agreement.ExitCode();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
