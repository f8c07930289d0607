#include "reconstruct/matting/cv_image.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {

cv::Mat RgbToMat(const FloatImage& photo) {
  SYLVA_CHECK(photo.channels() >= 3) << "photo needs 3 or 4 channels";
  cv::Mat rgb(photo.height(), photo.width(), CV_32FC3);
  const int channels = photo.channels();
  for (int y = 0; y < photo.height(); ++y) {
    const float* in = photo.data() + static_cast<size_t>(y) * photo.width() * channels;
    float* out = rgb.ptr<float>(y);
    for (int x = 0; x < photo.width(); ++x) {
      for (int c = 0; c < 3; ++c) out[3 * x + c] = in[channels * x + c];
    }
  }
  return rgb;
}

cv::Mat GrayToMat(const FloatImage& image) {
  SYLVA_CHECK(image.channels() == 1) << "expected one channel";
  return cv::Mat(image.height(), image.width(), CV_32FC1, const_cast<float*>(image.data())).clone();
}

FloatImage MatToImage(const cv::Mat& mat) {
  SYLVA_CHECK(mat.depth() == CV_32F && (mat.channels() == 1 || mat.channels() == 3));
  FloatImage image(mat.cols, mat.rows, mat.channels());
  const size_t row_floats = static_cast<size_t>(mat.cols) * mat.channels();
  for (int y = 0; y < mat.rows; ++y) {
    std::copy(mat.ptr<float>(y), mat.ptr<float>(y) + row_floats, image.data() + y * row_floats);
  }
  return image;
}

cv::Mat RgbToBgr8(const cv::Mat& rgb) {
  cv::Mat rgb8, bgr8;
  rgb.convertTo(rgb8, CV_8UC3, 255.0);  // saturating and rounding
  cv::cvtColor(rgb8, bgr8, cv::COLOR_RGB2BGR);
  return bgr8;
}

int ReductionFactor(cv::Size size, double max_megapixels) {
  const double megapixels = static_cast<double>(size.width) * size.height / 1e6;
  return std::max(1, static_cast<int>(std::ceil(std::sqrt(megapixels / max_megapixels))));
}

cv::Size ReducedSize(cv::Size size, int factor) {
  return cv::Size((size.width + factor - 1) / factor, (size.height + factor - 1) / factor);
}

cv::Mat Disk(int radius) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
}

}  // namespace sylva
