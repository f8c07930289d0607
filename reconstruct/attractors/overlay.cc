#include "reconstruct/attractors/overlay.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Fixed-point bits of the drawing coordinates (1/16 pixel).
constexpr int kShift = 4;
// Shorter image side per pixel of line width.
constexpr double kPixelsPerLineWidth = 300.0;
const cv::Scalar kEdgeColour(255, 40, 220);
const cv::Scalar kTipColour(255, 230, 0);
const cv::Scalar kJunctionColour(0, 230, 255);
const cv::Scalar kRootColour(235, 20, 20);
const cv::Scalar kRimColour(255, 255, 255);

// Draws on a premultiplied colour layer and its coverage at once, so that
// the layer composites "over" the photo.
class OverlayCanvas {
 public:
  OverlayCanvas(int width, int height)
      : colour_(height, width, CV_8UC3, cv::Scalar::all(0)),
        coverage_(height, width, CV_8UC1, cv::Scalar(0)) {}

  void Line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const cv::Scalar& colour,
            int width) {
    cv::line(colour_, Fixed(a), Fixed(b), colour, width, cv::LINE_AA, kShift);
    cv::line(coverage_, Fixed(a), Fixed(b), cv::Scalar(255), width, cv::LINE_AA, kShift);
  }
  // thickness < 0 fills.
  void Circle(const Eigen::Vector2d& c, double radius, const cv::Scalar& colour, int thickness) {
    const int r = static_cast<int>(std::lround(radius * (1 << kShift)));
    cv::circle(colour_, Fixed(c), r, colour, thickness, cv::LINE_AA, kShift);
    cv::circle(coverage_, Fixed(c), r, cv::Scalar(255), thickness, cv::LINE_AA, kShift);
  }

  // photo * (1 - coverage) + layer, per pixel; untouched pixels keep the photo.
  FloatImage Over(const FloatImage& rgb) const {
    FloatImage out = rgb;
    for (int y = 0; y < rgb.height(); ++y) {
      for (int x = 0; x < rgb.width(); ++x) {
        const float alpha = coverage_.at<uchar>(y, x) / 255.0f;
        if (alpha == 0) continue;
        const cv::Vec3b c = colour_.at<cv::Vec3b>(y, x);
        for (int k = 0; k < 3; ++k) out.at(x, y, k) = rgb.at(x, y, k) * (1 - alpha) + c[k] / 255.0f;
      }
    }
    return out;
  }

 private:
  // OpenCV puts pixel centres at integers, COLMAP at i + 0.5.
  static cv::Point Fixed(const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround((p.x() - 0.5) * (1 << kShift))),
                     static_cast<int>(std::lround((p.y() - 0.5) * (1 << kShift))));
  }

  cv::Mat colour_;  // premultiplied RGB
  cv::Mat coverage_;
};

FloatImage RgbOverWhite(const FloatImage& photo) {
  FloatImage rgb(photo.width(), photo.height(), 3);
  const bool has_alpha = photo.channels() == 4;
  for (int y = 0; y < photo.height(); ++y) {
    for (int x = 0; x < photo.width(); ++x) {
      const float alpha = has_alpha ? photo.at(x, y, 3) : 1.0f;
      for (int k = 0; k < 3; ++k) rgb.at(x, y, k) = photo.at(x, y, k) * alpha + (1 - alpha);
    }
  }
  return rgb;
}

}  // namespace

FloatImage DrawAttractorOverlay(const FloatImage& photo, const AttractorGraph2D& graph) {
  SYLVA_CHECK_INPUT(photo.channels() == 3 || photo.channels() == 4, "photo")
      << "expected an RGB or RGBA image, got " << photo.channels() << " channels";
  SYLVA_CHECK_INPUT(graph.width == photo.width() && graph.height == photo.height(),
                    "attractor graph")
      << "refers to a " << graph.width << " x " << graph.height << " image, the photo is "
      << photo.width() << " x " << photo.height();
  const int width = std::max(
      1,
      static_cast<int>(std::lround(std::min(photo.width(), photo.height()) / kPixelsPerLineWidth)));
  OverlayCanvas canvas(photo.width(), photo.height());
  for (const auto& [a, b] : graph.Segments()) canvas.Line(a, b, kEdgeColour, width);
  const std::vector<std::vector<int>> children = graph.Children();
  for (int i = 0; i < graph.NumNodes(); ++i) {
    const Eigen::Vector2d& p = graph.nodes[i].position;
    if (i == graph.root) continue;
    if (children[i].empty()) canvas.Circle(p, 1.5 * width, kTipColour, -1);
    if (children[i].size() >= 2) canvas.Circle(p, 3.0 * width, kJunctionColour, width);
  }
  if (graph.root >= 0) {
    canvas.Circle(graph.nodes[graph.root].position, 5.0 * width, kRimColour, -1);
    canvas.Circle(graph.nodes[graph.root].position, 3.5 * width, kRootColour, -1);
  }
  return canvas.Over(RgbOverWhite(photo));
}

}  // namespace sylva
