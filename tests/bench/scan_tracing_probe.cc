// By hand: traces scanned drawings (sketch/scan_tracing.h), prints each
// summary and, with --out=DIR, writes the strokes over the drawing (branches
// blue, crown outlines red, closed crowns thick; junction-free ends green).
//
// usage: sylva_scan_tracing_probe [--out=DIR] IMAGE...
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/check.h"
#include "sketch/scan_tracing.h"

namespace sylva {
namespace {

void WriteOverlay(const std::filesystem::path& image, const SketchDrawing& drawing,
                  const std::filesystem::path& out) {
  cv::Mat grey = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
  cv::Mat picture;
  cv::cvtColor(grey / 3 + 170, picture, cv::COLOR_GRAY2BGR);  // the drawing, faded
  for (const SketchStroke& s : drawing.strokes) {
    std::vector<cv::Point> points;
    for (const Eigen::Vector2d& p : s.points) points.emplace_back(p.x(), p.y());
    const bool crown = s.role == StrokeRole::kCrown;
    const cv::Scalar colour = crown ? cv::Scalar(0, 0, 230) : cv::Scalar(200, 60, 0);
    cv::polylines(picture, points, s.closed, colour, crown && s.closed ? 3 : 2, cv::LINE_AA);
    cv::circle(picture, points.front(), 3, cv::Scalar(0, 160, 0), cv::FILLED);
    cv::circle(picture, points.back(), 3, cv::Scalar(0, 160, 0), cv::FILLED);
  }
  cv::imwrite(out.string(), picture);
}

int Run(int argc, char** argv) {
  std::filesystem::path out_dir;
  int traced = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--out=", 6) == 0) {
      out_dir = argv[i] + 6;
      std::filesystem::create_directories(out_dir);
      continue;
    }
    const std::filesystem::path image = argv[i];
    ScanTracingSummary summary;
    const SketchDrawing drawing = TraceScannedDrawing(image, ScanTracingOptions(), &summary);
    std::printf("%s: %s\n", image.filename().c_str(), summary.BriefReport().c_str());
    if (drawing.root) std::printf("  root (%.1f, %.1f)\n", drawing.root->x(), drawing.root->y());
    if (!out_dir.empty()) {
      WriteOverlay(image, drawing, out_dir / (image.stem().string() + "_strokes.png"));
    }
    ++traced;
  }
  if (traced == 0) std::fprintf(stderr, "usage: %s [--out=DIR] IMAGE...\n", argv[0]);
  return traced > 0 ? 0 : 2;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    return sylva::Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
