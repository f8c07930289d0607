#include "reconstruct/matting/guided_upsample.h"

#include <opencv2/imgproc.hpp>

#include <vector>

namespace sylva {
namespace {

cv::Mat BoxMean(const cv::Mat& image, int radius) {
  cv::Mat mean;
  cv::boxFilter(image, mean, CV_32F, cv::Size(2 * radius + 1, 2 * radius + 1), cv::Point(-1, -1),
                true, cv::BORDER_REFLECT);
  return mean;
}

// The window-averaged affine coefficients: a (CV_32FC3) and b (CV_32FC1).
void AffineCoefficients(const cv::Mat& rgb, const cv::Mat& alpha, int radius, double epsilon,
                        cv::Mat* mean_a, cv::Mat* mean_b) {
  std::vector<cv::Mat> channel;
  cv::split(rgb, channel);
  const cv::Mat mean_rgb = BoxMean(rgb, radius);
  const cv::Mat mean_alpha = BoxMean(alpha, radius);
  cv::Mat mean_rgb_alpha[3], mean_products[3][3];
  for (int i = 0; i < 3; ++i) {
    mean_rgb_alpha[i] = BoxMean(channel[i].mul(alpha), radius);
    for (int j = i; j < 3; ++j) mean_products[i][j] = BoxMean(channel[i].mul(channel[j]), radius);
  }
  cv::Mat a(rgb.size(), CV_32FC3), b(rgb.size(), CV_32F);
  for (int y = 0; y < rgb.rows; ++y) {
    for (int x = 0; x < rgb.cols; ++x) {
      const cv::Vec3f mu = mean_rgb.at<cv::Vec3f>(y, x);
      const double mean_p = mean_alpha.at<float>(y, x);
      cv::Matx33d covariance;
      cv::Vec3d cross;
      for (int i = 0; i < 3; ++i) {
        cross[i] = mean_rgb_alpha[i].at<float>(y, x) - mu[i] * mean_p;
        for (int j = i; j < 3; ++j) {
          covariance(i, j) = covariance(j, i) = mean_products[i][j].at<float>(y, x) - mu[i] * mu[j];
        }
        covariance(i, i) += epsilon;
      }
      const cv::Vec3d coefficient = covariance.solve(cross, cv::DECOMP_CHOLESKY);
      a.at<cv::Vec3f>(y, x) = cv::Vec3f(coefficient);
      b.at<float>(y, x) = static_cast<float>(mean_p - coefficient.dot(cv::Vec3d(mu)));
    }
  }
  *mean_a = BoxMean(a, radius);
  *mean_b = BoxMean(b, radius);
}

}  // namespace

cv::Mat GuidedUpsample(const cv::Mat& small_rgb, const cv::Mat& small_alpha,
                       const cv::Mat& full_rgb, int radius, double epsilon) {
  cv::Mat small_a, small_b, full_a, full_b;
  AffineCoefficients(small_rgb, small_alpha, radius, epsilon, &small_a, &small_b);
  cv::resize(small_a, full_a, full_rgb.size(), 0, 0, cv::INTER_LINEAR);
  cv::resize(small_b, full_b, full_rgb.size(), 0, 0, cv::INTER_LINEAR);
  cv::Mat alpha(full_rgb.size(), CV_32F);
  for (int y = 0; y < full_rgb.rows; ++y) {
    for (int x = 0; x < full_rgb.cols; ++x) {
      const float value =
          full_a.at<cv::Vec3f>(y, x).dot(full_rgb.at<cv::Vec3f>(y, x)) + full_b.at<float>(y, x);
      alpha.at<float>(y, x) = std::min(1.0f, std::max(0.0f, value));
    }
  }
  return alpha;
}

}  // namespace sylva
