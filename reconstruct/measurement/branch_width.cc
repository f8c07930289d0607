#include "reconstruct/measurement/branch_width.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/util/check.h"
#include "core/util/statistics.h"
#include "core/util/threading.h"

namespace sylva {
namespace {

constexpr float kUnmeasured = std::numeric_limits<float>::quiet_NaN();
// Step of the search for the centre line across an edge (pixels).
constexpr double kSearchStep = 0.5;

// Distance (pixels) from each foreground pixel's centre to the nearest
// background pixel's centre; 0 on background.
cv::Mat DistanceToBackground(const FloatImage& matte, double threshold) {
  cv::Mat foreground(matte.height(), matte.width(), CV_8U);
  for (int y = 0; y < matte.height(); ++y) {
    auto* row = foreground.ptr<uint8_t>(y);
    for (int x = 0; x < matte.width(); ++x) row[x] = matte.at(x, y) >= threshold ? 255 : 0;
  }
  cv::Mat distance;
  cv::distanceTransform(foreground, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

float DistanceAt(const cv::Mat& distance, const Eigen::Vector2d& pixel) {
  const int x = static_cast<int>(std::floor(pixel.x()));
  const int y = static_cast<int>(std::floor(pixel.y()));
  if (x < 0 || y < 0 || x >= distance.cols || y >= distance.rows) return 0.0f;
  return distance.at<float>(y, x);
}

// The radius (world units) of the edge from `a` to `b` in one view, or NaN
// when the view does not see it side-on or finds no foreground near it.
float EdgeRadiusInView(const View& view, const Camera& camera, const cv::Mat& distance,
                       const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const BranchWidthOptions& options) {
  const Eigen::Vector3d a_cam = view.cam_from_world * a;
  const Eigen::Vector3d b_cam = view.cam_from_world * b;
  const Eigen::Vector3d mid_cam = 0.5 * (a_cam + b_cam);
  if (!camera.IsInFront(a_cam) || !camera.IsInFront(b_cam)) return kUnmeasured;
  const Eigen::Vector2d a_px = camera.ImgFromCam(a_cam);
  const Eigen::Vector2d b_px = camera.ImgFromCam(b_cam);
  const Eigen::Vector2d center = camera.ImgFromCam(mid_cam);
  const double world_per_pixel = camera.WorldPerPixel(mid_cam);
  const double length = (b - a).norm();
  const Eigen::Vector2d along = b_px - a_px;
  if (length <= 0 || along.norm() * world_per_pixel < options.min_side_on * length) {
    return kUnmeasured;
  }
  const Eigen::Vector2d across(-along.y() / along.norm(), along.x() / along.norm());
  // The centre line: the distance transform's largest value across the edge
  // (the nearer of equals).
  float best = 0.0f;
  for (double s = 0.0; s <= options.search_pixels; s += kSearchStep) {
    for (double sign : {1.0, -1.0}) {
      best = std::max(best, DistanceAt(distance, center + sign * s * across));
    }
  }
  if (best <= 0.0f) return kUnmeasured;
  // A run w pixels wide has its centre w/2 + 1/2 from the first background
  // pixel's centre.
  const double half_width = std::max(0.5, best - 0.5);
  return static_cast<float>(half_width * world_per_pixel);
}

// The value at `quantile` of the finite values, or NaN when fewer than `needed`.
double Quantile(std::vector<float> values, double quantile, int needed) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); }),
      values.end());
  if (static_cast<int>(values.size()) < needed || values.empty()) return kUnmeasured;
  const size_t k = static_cast<size_t>(std::floor(quantile * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

std::string BranchWidthSummary::BriefReport() const {
  std::ostringstream text;
  text.precision(3);
  text << "Radii measured in the mattes on " << measured_axes << " of " << num_axes
       << " branch axes (" << (total_length > 0 ? 100.0 * measured_length / total_length : 0.0)
       << " % of the length; the others scaled like their parent); trunk x" << trunk_scale
       << " the prior.";
  return text.str();
}

namespace {

// The radius of every edge (node -> parent) measured in the mattes: a low
// quantile over the views that see it side-on (kUnmeasured where too few
// do). The views one by one, so that one distance map at a time is held per
// thread.
std::vector<double> MeasuredEdgeRadii(const ImageSet& views, const std::vector<FloatImage>& mattes,
                                      const SkeletonGraph& skeleton,
                                      const BranchWidthOptions& options) {
  const int num_nodes = skeleton.NumNodes(), num_views = views.NumViews();
  std::vector<std::vector<float>> per_view(num_nodes, std::vector<float>(num_views, kUnmeasured));
  ParallelForFirstError(num_views, [&](int v) {
    const View& view = views.views[v];
    const Camera& camera = views.CameraOf(view);
    SYLVA_CHECK(mattes[v].width() == camera.width() && mattes[v].height() == camera.height())
        << "matte " << v << " does not match its camera's size";
    const cv::Mat distance = DistanceToBackground(mattes[v], options.matte_threshold);
    for (int i = 0; i < num_nodes; ++i) {
      const int parent = skeleton.nodes[i].parent_idx;
      if (parent < 0) continue;
      per_view[i][v] = EdgeRadiusInView(view, camera, distance, skeleton.nodes[parent].position,
                                        skeleton.nodes[i].position, options);
    }
  });
  std::vector<double> measured(num_nodes, kUnmeasured);
  for (int i = 0; i < num_nodes; ++i) {
    measured[i] = Quantile(per_view[i], options.view_quantile, options.min_views);
  }
  return measured;
}

// Each node's scale of its prior radius: per axis, parents' axes first (by
// branch order), the median of measured / prior where enough of the axis is
// measured, else the parent's scale; no child thicker than its parent where
// it leaves it. Fills the summary's axis counts and lengths.
std::vector<double> AxisScales(const SkeletonGraph& skeleton, const std::vector<double>& measured,
                               const std::vector<double>& prior, bool keep_trunk,
                               const BranchWidthOptions& options, BranchWidthSummary* summary) {
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = skeleton.BranchAxes(&orders);
  std::vector<int> by_order(axes.size());
  std::iota(by_order.begin(), by_order.end(), 0);
  std::stable_sort(by_order.begin(), by_order.end(),
                   [&](int a, int b) { return orders[a] < orders[b]; });
  std::vector<double> scale_of_node(skeleton.NumNodes(), 1.0);
  summary->num_axes = static_cast<int>(axes.size());
  for (int k : by_order) {
    const BranchAxis& axis = axes[k];
    const bool trunk = orders[k] == 0;
    double length = 0.0;
    std::vector<double> ratios;
    for (size_t j = 1; j < axis.size(); ++j) {
      const int i = axis[j];
      length += (skeleton.nodes[i].position - skeleton.nodes[axis[j - 1]].position).norm();
      if (std::isfinite(measured[i]) && prior[i] > 0) ratios.push_back(measured[i] / prior[i]);
    }
    summary->total_length += length;
    const int edges = static_cast<int>(axis.size()) - 1;
    const bool own = !(trunk && keep_trunk) && ratios.size() >= 2 &&
                     ratios.size() >= options.min_measured_share * edges;
    double scale = trunk ? 1.0 : scale_of_node[axis[0]];
    if (own) {
      scale = Median(ratios);
      ++summary->measured_axes;
      summary->measured_length += length;
    }
    // No thicker than its parent where it leaves it (the pipe model's
    // bound for one child: d^Delta <= d_parent^Delta).
    if (!trunk && axis.size() >= 2) {
      const double parent_radius = prior[axis[0]] * scale_of_node[axis[0]];
      const double first = prior[axis[1]] * scale;
      if (first > parent_radius && first > 0) scale *= parent_radius / first;
    }
    if (trunk) {
      summary->trunk_scale = scale;
      scale_of_node[axis[0]] = scale;  // the root
    }
    for (size_t j = 1; j < axis.size(); ++j) scale_of_node[axis[j]] = scale;
  }
  return scale_of_node;
}

}  // namespace

BranchWidthSummary MeasureBranchRadii(const ImageSet& views, const std::vector<FloatImage>& mattes,
                                      bool leafless, bool keep_trunk,
                                      const BranchWidthOptions& options, SkeletonGraph* skeleton) {
  options.Check();
  SYLVA_CHECK(skeleton != nullptr);
  SYLVA_CHECK(static_cast<int>(mattes.size()) == views.NumViews())
      << mattes.size() << " mattes for " << views.NumViews() << " views";
  BranchWidthSummary summary;
  const int num_nodes = skeleton->NumNodes();
  const bool enabled = options.mode == "on" || (options.mode == "auto" && leafless);
  if (num_nodes == 0 || !enabled) return summary;

  const std::vector<double> measured = MeasuredEdgeRadii(views, mattes, *skeleton, options);
  std::vector<double> prior(num_nodes);
  for (int i = 0; i < num_nodes; ++i) prior[i] = skeleton->nodes[i].radius;
  const std::vector<double> scale_of_node =
      AxisScales(*skeleton, measured, prior, keep_trunk, options, &summary);
  for (int i = 0; i < num_nodes; ++i) skeleton->nodes[i].radius = prior[i] * scale_of_node[i];
  if (summary.measured_axes > 0) skeleton->radius_source = kMattesMeasured;
  return summary;
}

}  // namespace sylva
