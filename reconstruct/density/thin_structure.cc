#include "reconstruct/density/thin_structure.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"
#include "core/util/threading.h"

namespace sylva {
namespace {

// Matte values at or above this are foreground.
constexpr float kForegroundAlpha = 0.5f;
// A voxel narrower than this many pixels cannot show structure thinner than
// itself at pixel precision.
constexpr double kMinVoxelPixels = 2.0;

// How wide a voxel of `voxel_size` at `center_in_world` appears in a view, in pixels.
double VoxelPixels(const ImageSet& image_set, int v, const Eigen::Vector3d& center_in_world,
                   double voxel_size) {
  const Camera& camera = image_set.CameraOf(v);
  const double focal = 0.5 * (camera.FocalLengthX() + camera.FocalLengthY());
  if (camera.IsOrthographic()) return focal * voxel_size;
  const double depth = (image_set.views[v].cam_from_world * center_in_world).z();
  return depth > 0 ? focal * voxel_size / depth : 0.0;
}

cv::Mat ForegroundMask(const FloatImage& matte) {
  cv::Mat mask(matte.height(), matte.width(), CV_8U);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      mask.at<uchar>(y, x) = matte.at(x, y) >= kForegroundAlpha ? 255 : 0;
    }
  }
  return mask;
}

// The ridge of the foreground's distance transform: pixels at least as far
// from the background as both neighbours along x or both along y. A line one
// to two pixels wide along the middle of every structure (a fast stand-in for
// thinning, whose iterations cost seconds per megapixel).
std::vector<cv::Point> CentreLine(const cv::Mat& mask) {
  cv::Mat distance;
  cv::distanceTransform(mask, distance, cv::DIST_L2, 3);
  std::vector<cv::Point> ridge;
  for (int y = 1; y + 1 < distance.rows; ++y) {
    const float* above = distance.ptr<float>(y - 1);
    const float* row = distance.ptr<float>(y);
    const float* below = distance.ptr<float>(y + 1);
    for (int x = 1; x + 1 < distance.cols; ++x) {
      const float d = row[x];
      if (d <= 0.0f) continue;
      const bool ridge_x = d >= row[x - 1] && d >= row[x + 1];
      const bool ridge_y = d >= above[x] && d >= below[x];
      if (ridge_x || ridge_y) ridge.emplace_back(x, y);
    }
  }
  return ridge;
}

}  // namespace

struct ThinStructureProbe::View {
  int view_idx = 0;
  cv::Mat mask;                        // foreground, CV_8U 0/255
  std::vector<cv::Point> centre_line;  // ridge pixels of the foreground (CentreLine)
};

ThinStructureProbe::ThinStructureProbe(const ImageSet& image_set,
                                       const std::vector<FloatImage>& mattes, int max_views)
    : image_set_(image_set) {
  SYLVA_CHECK(static_cast<int>(mattes.size()) == image_set.NumViews() && max_views >= 1);
  const int num_views = image_set.NumViews();
  const int used = std::min(num_views, max_views);
  views_.resize(used);
  ParallelForFirstError(used, [&](int k) {
    auto view = std::make_unique<View>();
    view->view_idx = static_cast<int>(static_cast<int64_t>(k) * num_views / used);
    view->mask = ForegroundMask(mattes[view->view_idx]);
    view->centre_line = CentreLine(view->mask);
    views_[k] = std::move(view);
  });
}

ThinStructureProbe::~ThinStructureProbe() = default;

double ThinStructureProbe::ThinShare(const Eigen::Vector3d& center_in_world,
                                     double voxel_size) const {
  std::vector<int64_t> length(views_.size(), 0), thin(views_.size(), 0);
  ParallelForFirstError(static_cast<int>(views_.size()), [&](int k) {
    const View& view = *views_[k];
    const double diameter = VoxelPixels(image_set_, view.view_idx, center_in_world, voxel_size);
    if (diameter < kMinVoxelPixels || view.centre_line.empty()) return;
    const int size = static_cast<int>(std::lround(diameter));
    cv::Mat opened, distance;
    cv::morphologyEx(view.mask, opened, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
    // Distance of every pixel to the thick structure (what the opening kept).
    cv::distanceTransform(opened == 0, distance, cv::DIST_L2, 3);
    const float far = static_cast<float>(0.5 * diameter);
    for (const cv::Point& p : view.centre_line) thin[k] += distance.at<float>(p) > far;
    length[k] = static_cast<int64_t>(view.centre_line.size());
  });
  int64_t all = 0, thin_all = 0;
  for (size_t k = 0; k < views_.size(); ++k) {
    all += length[k];
    thin_all += thin[k];
  }
  return all > 0 ? static_cast<double>(thin_all) / all : 0.0;
}

bool ThinStructureProbe::Resolvable(const Eigen::Vector3d& center_in_world,
                                    double voxel_size) const {
  int wide_enough = 0;
  for (const auto& view : views_) {
    wide_enough +=
        VoxelPixels(image_set_, view->view_idx, center_in_world, voxel_size) >= kMinVoxelPixels;
  }
  return 2 * wide_enough > static_cast<int>(views_.size());
}

}  // namespace sylva
