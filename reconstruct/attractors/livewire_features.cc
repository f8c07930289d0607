#include "reconstruct/attractors/livewire_features.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"
#include "reconstruct/matting/cv_image.h"

namespace sylva {
namespace {

// Smoothing of the distance transform before its gradients are taken, and of
// the structure tensor, in traced pixels.
constexpr double kDistanceSigma = 1.0;
constexpr double kTensorSigma = 2.0;
// Orientations are left at zero where the tensor's anisotropy
// (lambda1 - lambda2) is below this (squared distance units per pixel^2).
constexpr double kMinAnisotropy = 1e-3;

void CheckLivewireImages(const FloatImage& photo, const FloatImage& matte) {
  SYLVA_CHECK_INPUT(!photo.empty() && (photo.channels() == 3 || photo.channels() == 4), "photo")
      << "expected an RGB or RGBA image, got " << photo.width() << " x " << photo.height()
      << " with " << photo.channels() << " channels";
  SYLVA_CHECK_INPUT(matte.channels() == 1, "matte")
      << "expected one channel, got " << matte.channels();
  SYLVA_CHECK_INPUT(matte.width() == photo.width() && matte.height() == photo.height(), "matte")
      << "size " << matte.width() << " x " << matte.height() << " differs from the photo's "
      << photo.width() << " x " << photo.height();
}

cv::Mat Reduce(const cv::Mat& image, cv::Size size) {
  if (image.size() == size) return image;
  cv::Mat reduced;
  cv::resize(image, reduced, size, 0, 0, cv::INTER_AREA);
  return reduced;
}

// Unit gradient orientation of the smoothed distance transform from its
// structure tensor: sign-free, so it stays defined on a branch's centre line
// where the gradient itself vanishes. cos(angle) >= 0 fixes the sign.
cv::Mat BranchOrientation(const cv::Mat& distance) {
  cv::Mat smooth, gx, gy;
  cv::GaussianBlur(distance, smooth, cv::Size(), kDistanceSigma);
  cv::Sobel(smooth, gx, CV_32F, 1, 0, 3, 1.0 / 8);
  cv::Sobel(smooth, gy, CV_32F, 0, 1, 3, 1.0 / 8);
  cv::Mat jxx = gx.mul(gx), jxy = gx.mul(gy), jyy = gy.mul(gy);
  for (cv::Mat* j : {&jxx, &jxy, &jyy}) cv::GaussianBlur(*j, *j, cv::Size(), kTensorSigma);
  cv::Mat orientation(distance.size(), CV_32FC2, cv::Scalar::all(0));
  for (int y = 0; y < distance.rows; ++y) {
    for (int x = 0; x < distance.cols; ++x) {
      const double a = jxx.at<float>(y, x), b = jxy.at<float>(y, x), c = jyy.at<float>(y, x);
      const double anisotropy = std::hypot(a - c, 2 * b);  // lambda1 - lambda2
      if (anisotropy < kMinAnisotropy) continue;
      const double angle = 0.5 * std::atan2(2 * b, a - c);
      orientation.at<cv::Vec2f>(y, x) = cv::Vec2f(std::cos(angle), std::sin(angle));
    }
  }
  return orientation;
}

// (1 - photo_weight) / (1 + distance) + photo_weight * luminance on the tree,
// 1 off it.
cv::Mat CenterlineCost(const cv::Mat& rgb, const cv::Mat& mask, const cv::Mat& distance,
                       double photo_weight) {
  cv::Mat luminance;
  cv::cvtColor(rgb, luminance, cv::COLOR_RGB2GRAY);
  cv::Mat cost(mask.size(), CV_32FC1, cv::Scalar(1));
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      const double lum = std::clamp(luminance.at<float>(y, x), 0.0f, 1.0f);
      cost.at<float>(y, x) = static_cast<float>(
          (1 - photo_weight) / (1 + distance.at<float>(y, x)) + photo_weight * lum);
    }
  }
  return cost;
}

}  // namespace

cv::Point LivewireFeatures::ToTraced(const Eigen::Vector2d& point_in_image) const {
  const int x = static_cast<int>(std::floor(point_in_image.x() * scale_x));
  const int y = static_cast<int>(std::floor(point_in_image.y() * scale_y));
  return cv::Point(std::clamp(x, 0, mask.cols - 1), std::clamp(y, 0, mask.rows - 1));
}

Eigen::Vector2d LivewireFeatures::ToFull(const cv::Point& pixel) const {
  return Eigen::Vector2d((pixel.x + 0.5) / scale_x, (pixel.y + 0.5) / scale_y);
}

LivewireFeatures ComputeLivewireFeatures(const FloatImage& photo, const FloatImage& matte,
                                         const LivewireOptions& options) {
  CheckLivewireImages(photo, matte);
  LivewireFeatures features;
  features.full_width = photo.width();
  features.full_height = photo.height();
  const double scale = std::min(
      1.0, static_cast<double>(options.max_image_size) / std::max(photo.width(), photo.height()));
  const cv::Size size(std::max(1, static_cast<int>(std::lround(photo.width() * scale))),
                      std::max(1, static_cast<int>(std::lround(photo.height() * scale))));
  features.scale_x = static_cast<double>(size.width) / photo.width();
  features.scale_y = static_cast<double>(size.height) / photo.height();

  const cv::Mat rgb = Reduce(RgbToMat(photo), size);
  const cv::Mat alpha = Reduce(GrayToMat(matte), size);
  features.mask = alpha >= options.matte_threshold;  // 0 / 255
  features.mask /= 255;
  SYLVA_CHECK_INPUT(cv::countNonZero(features.mask) > 0, "matte")
      << "no pixel reaches Attractors.matte_threshold " << options.matte_threshold
      << ": nothing to trace";
  features.outside = 1 - features.mask;
  cv::Mat distance;
  cv::distanceTransform(features.mask, distance, cv::DIST_L2, cv::DIST_MASK_5);
  features.direction = BranchOrientation(distance);
  features.centerline = CenterlineCost(rgb, features.mask, distance, options.photo_weight);
  return features;
}

}  // namespace sylva
