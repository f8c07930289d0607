#include "reconstruct/matting/backdrop.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "reconstruct/matting/option_parsing.h"

namespace sylva {
namespace {

// Longer side of the reduced image on which the clean plate is estimated.
constexpr int kPlateLongSide = 512;
// Re-selections of the backdrop pixels against the current plate.
constexpr int kPlateIterations = 3;
// Border luminance percentiles that bound the initial backdrop selection.
constexpr double kBorderLowPercentile = 0.02;
constexpr double kBorderHighPercentile = 0.98;

struct EvidenceParams {
  double inv_chroma_tolerance;
  double inv_luminance_tolerance;
  double dark_norm;  // dark_level * sqrt(3): floor of |p| in the chroma ratio
};

EvidenceParams MakeParams(const MattingOptions& options) {
  return {1.0 / options.chroma_tolerance, 1.0 / options.luminance_tolerance,
          options.dark_level * std::sqrt(3.0)};
}

// Sine of the angle between p and the backdrop colour b (floored at dark).
double Chroma(const cv::Vec3f& p, const cv::Vec3f& b, double dark_norm) {
  const double b_norm = std::sqrt(b.dot(b));
  const cv::Vec3d dir = b_norm > 1e-6 ? cv::Vec3d(b) / b_norm : cv::Vec3d(1, 1, 1) / std::sqrt(3.0);
  const cv::Vec3d pd(p);
  const cv::Vec3d perp = pd - pd.dot(dir) * dir;
  return std::sqrt(perp.dot(perp)) / std::max(std::sqrt(pd.dot(pd)), dark_norm);
}

double Luminance(const cv::Vec3f& p) { return (p[0] + p[1] + p[2]) / 3.0; }

double Evidence(const cv::Vec3f& p, const cv::Vec3f& b, const EvidenceParams& e) {
  return std::max(Chroma(p, b, e.dark_norm) * e.inv_chroma_tolerance,
                  std::abs(Luminance(p) - Luminance(b)) * e.inv_luminance_tolerance);
}

// Evidence of every pixel of `rgb` against the per-pixel plate.
cv::Mat EvidenceMap(const cv::Mat& rgb, const cv::Mat& plate, const EvidenceParams& params) {
  cv::Mat evidence(rgb.size(), CV_32F);
  cv::parallel_for_(cv::Range(0, rgb.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3f* p = rgb.ptr<cv::Vec3f>(y);
      const cv::Vec3f* b = plate.ptr<cv::Vec3f>(y);
      float* out = evidence.ptr<float>(y);
      for (int x = 0; x < rgb.cols; ++x) out[x] = static_cast<float>(Evidence(p[x], b[x], params));
    }
  });
  return evidence;
}

std::vector<cv::Vec3f> BorderPixels(const cv::Mat& rgb, double border_fraction) {
  const int strip =
      std::max(2, static_cast<int>(std::lround(border_fraction * std::min(rgb.cols, rgb.rows))));
  std::vector<cv::Vec3f> pixels;
  for (int y = 0; y < rgb.rows; ++y) {
    const bool full_row = y < strip || y >= rgb.rows - strip;
    for (int x = 0; x < rgb.cols; ++x) {
      if (full_row || x < strip || x >= rgb.cols - strip) pixels.push_back(rgb.at<cv::Vec3f>(y, x));
    }
  }
  return pixels;
}

double Quantile(std::vector<double> values, double q) {
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

cv::Vec3f MedianColor(const std::vector<cv::Vec3f>& pixels) {
  cv::Vec3f median;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> channel(pixels.size());
    for (size_t i = 0; i < pixels.size(); ++i) channel[i] = pixels[i][c];
    median[c] = static_cast<float>(Quantile(std::move(channel), 0.5));
  }
  return median;
}

// Pixels that may be backdrop before any plate exists: chroma close to the
// seed's and luminance within the border's range widened by the tolerance.
cv::Mat InitialSelection(const cv::Mat& rgb, const cv::Vec3f& seed,
                         const std::vector<cv::Vec3f>& border, const MattingOptions& options) {
  std::vector<double> lum(border.size());
  for (size_t i = 0; i < border.size(); ++i) lum[i] = Luminance(border[i]);
  const double seed_lum = Luminance(seed);
  const double lo =
      std::min(Quantile(lum, kBorderLowPercentile), seed_lum) - options.luminance_tolerance;
  const double hi =
      std::max(Quantile(lum, kBorderHighPercentile), seed_lum) + options.luminance_tolerance;
  const double dark_norm = options.dark_level * std::sqrt(3.0);
  cv::Mat selection(rgb.size(), CV_32F);
  for (int y = 0; y < rgb.rows; ++y) {
    for (int x = 0; x < rgb.cols; ++x) {
      const cv::Vec3f& p = rgb.at<cv::Vec3f>(y, x);
      const double l = Luminance(p);
      selection.at<float>(y, x) =
          Chroma(p, seed, dark_norm) < options.chroma_tolerance && l >= lo && l <= hi;
    }
  }
  return selection;
}

// Normalised convolution: the Gaussian-weighted mean of the selected pixels;
// the seed colour where (almost) nothing is selected nearby.
cv::Mat AverageSelected(const cv::Mat& rgb, const cv::Mat& selection, double sigma,
                        const cv::Vec3f& seed) {
  cv::Mat weighted, weights;
  cv::Mat selection3;
  cv::merge(std::vector<cv::Mat>{selection, selection, selection}, selection3);
  cv::GaussianBlur(rgb.mul(selection3), weighted, cv::Size(), sigma, sigma, cv::BORDER_REFLECT);
  cv::GaussianBlur(selection, weights, cv::Size(), sigma, sigma, cv::BORDER_REFLECT);
  constexpr float kMinWeight = 1e-3f;
  cv::Mat plate(rgb.size(), CV_32FC3);
  for (int y = 0; y < rgb.rows; ++y) {
    for (int x = 0; x < rgb.cols; ++x) {
      const float w = weights.at<float>(y, x);
      plate.at<cv::Vec3f>(y, x) = w > kMinWeight ? weighted.at<cv::Vec3f>(y, x) / w : seed;
    }
  }
  return plate;
}

// The clean plate at the photo's size (see backdrop.h).
cv::Mat EstimatePlate(const cv::Mat& rgb, const cv::Vec3f& seed,
                      const std::vector<cv::Vec3f>& border, const MattingOptions& options) {
  const double scale =
      std::min(1.0, static_cast<double>(kPlateLongSide) / std::max(rgb.cols, rgb.rows));
  cv::Mat small;
  cv::resize(rgb, small, cv::Size(), scale, scale, cv::INTER_AREA);
  const double sigma = options.backdrop_smoothness * std::max(small.cols, small.rows);
  const EvidenceParams params = MakeParams(options);
  cv::Mat selection = InitialSelection(small, seed, border, options);
  cv::Mat plate = AverageSelected(small, selection, sigma, seed);
  for (int i = 0; i < kPlateIterations; ++i) {
    cv::Mat below_one = EvidenceMap(small, plate, params) < 1.0f;
    below_one.convertTo(selection, CV_32F, 1.0 / 255.0);
    plate = AverageSelected(small, selection, sigma, seed);
  }
  cv::Mat full;
  cv::resize(plate, full, rgb.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

}  // namespace

BackdropKey EstimateBackdropKey(const cv::Mat& rgb, const MattingOptions& options) {
  const std::vector<cv::Vec3f> border = BorderPixels(rgb, options.border_fraction);
  const std::optional<std::array<double, 3>> given = ParseBackdropColor(options.backdrop_color);
  const cv::Vec3f seed =
      given ? cv::Vec3f((*given)[0], (*given)[1], (*given)[2]) : MedianColor(border);
  const EvidenceParams params = MakeParams(options);
  size_t agreeing = 0;
  for (const cv::Vec3f& p : border) agreeing += Evidence(p, seed, params) < 1.0;
  BackdropKey key;
  for (int c = 0; c < 3; ++c) key.seed_rgb[c] = seed[c];
  key.border_agreement = static_cast<double>(agreeing) / border.size();
  return key;
}

cv::Mat BackdropEvidence(const cv::Mat& rgb, const MattingOptions& options, const BackdropKey& key,
                         const cv::Mat& background_rgb) {
  cv::Mat plate;
  if (!background_rgb.empty()) {
    plate = background_rgb;
  } else {
    const cv::Vec3f seed(key.seed_rgb[0], key.seed_rgb[1], key.seed_rgb[2]);
    plate = EstimatePlate(rgb, seed, BorderPixels(rgb, options.border_fraction), options);
  }
  return EvidenceMap(rgb, plate, MakeParams(options));
}

}  // namespace sylva
