#include "reconstruct/registration/world_frame.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>

#include "core/util/check.h"

namespace sylva {
namespace {

// Camera x axes that all lie within this angle of one direction (sin^2 of
// ~10 degrees, as an eigenvalue per view) leave up undetermined about it.
constexpr double kMinHorizonSpread = 0.03;
// Rays whose normal matrix has a smallest eigenvalue per ray below this are
// (nearly) parallel: no triangulation.
constexpr double kMinRaySpread = 1e-4;
// Relative size of the step used to find the image direction of up.
constexpr double kUpProbeFraction = 1e-3;
// A point seen by a single matte is not confirmed by any other.
constexpr int kMinSeeingViews = 2;
// Matte sizes may differ from their camera's by rounding; aspect ratios must
// agree within this fraction.
constexpr double kMaxAspectMismatch = 0.01;

Eigen::Vector3d AxisDirection(const std::string& name) {
  const int index = static_cast<int>(
      std::find(std::begin(kUpAxisNames), std::end(kUpAxisNames), name) - std::begin(kUpAxisNames));
  SYLVA_CHECK(index < 6) << "unknown axis " << name;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  axis(index / 2) = index % 2 == 0 ? 1.0 : -1.0;
  return axis;
}

// The quarter or half turn about a coordinate axis taking `axis` (a signed
// coordinate axis) to +Z; the coordinate axis turned about is kept.
Eigen::Quaterniond AxisToZ(const Eigen::Vector3d& axis) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  if (axis.z() > 0.5) return Eigen::Quaterniond::Identity();
  if (axis.z() < -0.5) return Eigen::Quaterniond(AngleAxisd(M_PI, Vector3d::UnitX()));
  if (std::abs(axis.x()) > 0.5) {
    return Eigen::Quaterniond(AngleAxisd(-axis.x() * M_PI / 2, Vector3d::UnitY()));
  }
  return Eigen::Quaterniond(AngleAxisd(axis.y() * M_PI / 2, Vector3d::UnitX()));
}

Eigen::Vector3d CameraAxisInWorld(const View& view, int axis) {
  return view.cam_from_world.rotation.inverse() * Eigen::Vector3d::Unit(axis);
}

// Eigen decomposition of a symmetric 3x3 matrix, eigenvalues ascending.
Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> Eigen3(const Eigen::Matrix3d& matrix) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(matrix);
}

// ---------------------------------------------------------------------------
// Up.

struct UpEstimate {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::string source;
};

// Up from how the cameras are held: perpendicular to every camera's x axis
// (level for upright photos, whatever the pitch), pointing like their image
// up (-y); the mean image up if the x axes are (nearly) parallel.
UpEstimate CameraUpright(const ImageSet& cameras) {
  Eigen::Matrix3d horizons = Eigen::Matrix3d::Zero();
  Eigen::Vector3d image_up = Eigen::Vector3d::Zero();
  for (const View& view : cameras.views) {
    const Eigen::Vector3d x_axis = CameraAxisInWorld(view, 0);
    horizons += x_axis * x_axis.transpose();
    image_up -= CameraAxisInWorld(view, 1);
  }
  const int n = cameras.NumViews();
  const auto solver = Eigen3(horizons);
  UpEstimate estimate;
  if (n >= 2 && solver.eigenvalues()(1) >= kMinHorizonSpread * n) {
    estimate.up = solver.eigenvectors().col(0);
    if (estimate.up.dot(image_up) < 0) estimate.up = -estimate.up;
    estimate.source = "level camera x axes (" + std::to_string(n) + " views)";
  } else {
    estimate.up = image_up.normalized();
    estimate.source = "camera image up (" + std::to_string(n) + (n == 1 ? " view)" : " views)");
  }
  return estimate;
}

// The normal of the ring of camera centres, oriented along `upright`, if the
// centres form a ring (see WorldFrameOptions).
std::optional<Eigen::Vector3d> RingNormal(const ImageSet& cameras, const Eigen::Vector3d& upright,
                                          const WorldFrameOptions& options) {
  const int n = cameras.NumViews();
  if (n < options.ring_min_views) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const View& view : cameras.views) mean += view.ProjectionCenter() / n;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const View& view : cameras.views) {
    const Eigen::Vector3d offset = view.ProjectionCenter() - mean;
    covariance += offset * offset.transpose() / n;
  }
  const auto solver = Eigen3(covariance);
  const Eigen::Vector3d spread = solver.eigenvalues().cwiseMax(0).cwiseSqrt();
  if (!(spread(1) > 0) || spread(0) > options.ring_max_thickness * spread(1)) {
    return std::nullopt;
  }
  Eigen::Vector3d normal = solver.eigenvectors().col(0);
  if (normal.dot(upright) < 0) normal = -normal;
  if (normal.dot(upright) < std::cos(options.ring_max_tilt_degrees * M_PI / 180)) {
    return std::nullopt;
  }
  return normal;
}

UpEstimate EstimateUp(const ImageSet& cameras, const WorldFrameOptions& options) {
  UpEstimate estimate;
  if (options.up == "keep") {
    estimate.source = "kept (+z)";
  } else if (options.up != "auto") {
    estimate.up = AxisDirection(options.up);
    estimate.source = "option " + options.up;
  } else {
    estimate = CameraUpright(cameras);
    if (const auto ring = RingNormal(cameras, estimate.up, options)) {
      estimate.up = *ring;
      estimate.source = "camera ring (" + std::to_string(cameras.NumViews()) + " views)";
    }
  }
  return estimate;
}

// ---------------------------------------------------------------------------
// Mattes.

// One view's matte, reduced for the analysis: the kept foreground (large
// parts only) at working resolution, and its lowest and highest bands.
class MatteView {
 public:
  MatteView(const ImageSet& cameras, int view_idx, const FloatImage& matte,
            const Eigen::Vector3d& up, double scene_scale, const WorldFrameOptions& options);

  bool usable() const { return usable_; }
  // Band centroids in the camera's pixel coordinates.
  const Eigen::Vector2d& bottom() const { return bottom_; }
  const Eigen::Vector2d& top() const { return top_; }
  // Whether a camera pixel is foreground, with one working pixel of slack.
  bool Covers(const Eigen::Vector2d& point_in_image) const;

 private:
  void KeepLargeParts(const WorldFrameOptions& options);
  Eigen::Vector2d CameraPixel(int x, int y) const;
  void FindBands(const Eigen::Vector2d& image_up, double band_fraction);

  bool usable_ = false;
  int width_ = 0;
  int height_ = 0;
  Eigen::Vector2d mask_from_camera_ = Eigen::Vector2d::Ones();  // scale per axis
  std::vector<uint8_t> foreground_;                             // kept parts
  std::vector<uint8_t> covered_;                                // kept parts dilated by one pixel
  Eigen::Vector2d bottom_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d top_ = Eigen::Vector2d::Zero();
};

// The image direction (unit, pixels) in which a world point moves when it
// moves up, at pixel `at` of view `view_idx`.
Eigen::Vector2d ImageUpDirection(const ImageSet& cameras, int view_idx, const Eigen::Vector2d& at,
                                 const Eigen::Vector3d& up, double scene_scale) {
  const Ray3d ray = cameras.RayThroughPixel(view_idx, at);
  const Eigen::Vector3d point = ray.origin + scene_scale * ray.direction;
  Eigen::Vector2d below, above;
  if (!cameras.Project(view_idx, point, &below) ||
      !cameras.Project(view_idx, point + kUpProbeFraction * scene_scale * up, &above) ||
      (above - below).norm() == 0) {
    return Eigen::Vector2d(0, -1);
  }
  return (above - below).normalized();
}

MatteView::MatteView(const ImageSet& cameras, int view_idx, const FloatImage& matte,
                     const Eigen::Vector3d& up, double scene_scale,
                     const WorldFrameOptions& options) {
  if (matte.empty()) return;
  const Camera& camera = cameras.CameraOf(view_idx);
  const std::string source = "mattes (view '" + cameras.views[view_idx].name + "')";
  SYLVA_CHECK_INPUT(matte.channels() == 1, source)
      << "a matte has one channel, this one has " << matte.channels();
  const double scale_x = static_cast<double>(matte.width()) / camera.width();
  const double scale_y = static_cast<double>(matte.height()) / camera.height();
  SYLVA_CHECK_INPUT(std::abs(scale_x / scale_y - 1) <= kMaxAspectMismatch, source)
      << "the matte is " << matte.width() << "x" << matte.height() << " but its camera is "
      << camera.width() << "x" << camera.height() << " (another aspect ratio)";
  const int factor = std::max(
      1, static_cast<int>(std::ceil(static_cast<double>(std::max(matte.width(), matte.height())) /
                                    options.matte_working_size)));
  const FloatImage small = DownsampleBox(matte, factor);
  width_ = small.width();
  height_ = small.height();
  mask_from_camera_ = Eigen::Vector2d(scale_x, scale_y) / factor;
  foreground_.resize(small.NumPixels());
  for (size_t i = 0; i < foreground_.size(); ++i) {
    foreground_[i] = small.data()[i] > options.matte_threshold ? 1 : 0;
  }
  KeepLargeParts(options);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double count = 0;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!foreground_[y * width_ + x]) continue;
      centroid += CameraPixel(x, y);
      count += 1;
    }
  }
  if (count == 0) return;
  centroid /= count;
  FindBands(ImageUpDirection(cameras, view_idx, centroid, up, scene_scale), options.band_fraction);
  usable_ = true;
}

// Labels 4-connected parts and clears those smaller than min_part_fraction
// of the largest; then dilates what is left by one pixel into covered_.
void MatteView::KeepLargeParts(const WorldFrameOptions& options) {
  std::vector<int> label(foreground_.size(), -1);
  std::vector<int> part_sizes;
  std::vector<int> stack;
  for (int start = 0; start < static_cast<int>(foreground_.size()); ++start) {
    if (!foreground_[start] || label[start] >= 0) continue;
    const int part = static_cast<int>(part_sizes.size());
    part_sizes.push_back(0);
    label[start] = part;
    stack.push_back(start);
    while (!stack.empty()) {
      const int pixel = stack.back();
      stack.pop_back();
      ++part_sizes[part];
      const int x = pixel % width_, y = pixel / width_;
      const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& [nx, ny] : neighbours) {
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        const int next = ny * width_ + nx;
        if (!foreground_[next] || label[next] >= 0) continue;
        label[next] = part;
        stack.push_back(next);
      }
    }
  }
  const int largest =
      part_sizes.empty() ? 0 : *std::max_element(part_sizes.begin(), part_sizes.end());
  for (size_t i = 0; i < foreground_.size(); ++i) {
    if (foreground_[i] && part_sizes[label[i]] < options.min_part_fraction * largest) {
      foreground_[i] = 0;
    }
  }
  covered_.assign(foreground_.size(), 0);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!foreground_[y * width_ + x]) continue;
      for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny) {
        for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) {
          covered_[ny * width_ + nx] = 1;
        }
      }
    }
  }
}

Eigen::Vector2d MatteView::CameraPixel(int x, int y) const {
  return Eigen::Vector2d(x + 0.5, y + 0.5).cwiseQuotient(mask_from_camera_);
}

// Centroids of the foreground pixels in the lowest and highest bands along
// `image_up`.
void MatteView::FindBands(const Eigen::Vector2d& image_up, double band_fraction) {
  double lowest = INFINITY, highest = -INFINITY;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!foreground_[y * width_ + x]) continue;
      const double height = CameraPixel(x, y).dot(image_up);
      lowest = std::min(lowest, height);
      highest = std::max(highest, height);
    }
  }
  // At least one working pixel thick.
  const double band =
      std::max(band_fraction * (highest - lowest), 1.0 / mask_from_camera_.minCoeff());
  Eigen::Vector2d bottom_sum = Eigen::Vector2d::Zero(), top_sum = Eigen::Vector2d::Zero();
  double bottom_count = 0, top_count = 0;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!foreground_[y * width_ + x]) continue;
      const Eigen::Vector2d pixel = CameraPixel(x, y);
      const double height = pixel.dot(image_up);
      if (height <= lowest + band) bottom_sum += pixel, bottom_count += 1;
      if (height >= highest - band) top_sum += pixel, top_count += 1;
    }
  }
  bottom_ = bottom_sum / bottom_count;
  top_ = top_sum / top_count;
}

bool MatteView::Covers(const Eigen::Vector2d& point_in_image) const {
  const Eigen::Vector2d in_mask = point_in_image.cwiseProduct(mask_from_camera_);
  const int x = static_cast<int>(std::floor(in_mask.x()));
  const int y = static_cast<int>(std::floor(in_mask.y()));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
  return covered_[y * width_ + x] != 0;
}

// ---------------------------------------------------------------------------
// Base and height.

// The point closest (least squares) to all rays, if they are not parallel.
std::optional<Eigen::Vector3d> Triangulate(const std::vector<Ray3d>& rays) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Ray3d& ray : rays) {
    const Eigen::Matrix3d across =
        Eigen::Matrix3d::Identity() - ray.direction * ray.direction.transpose();
    normal += across;
    rhs += across * ray.origin;
  }
  if (rays.size() < 2 || Eigen3(normal).eigenvalues()(0) < kMinRaySpread * rays.size()) {
    return std::nullopt;
  }
  return Eigen::Vector3d(normal.ldlt().solve(rhs));
}

// Spread of the camera centres (RMS distance from their mean), or 1.
double SceneScale(const ImageSet& cameras) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const View& view : cameras.views) mean += view.ProjectionCenter() / cameras.NumViews();
  double sum = 0;
  for (const View& view : cameras.views) sum += (view.ProjectionCenter() - mean).squaredNorm();
  const double scale = std::sqrt(sum / cameras.NumViews());
  return scale > 0 ? scale : 1.0;
}

struct Analysis {
  const ImageSet* cameras = nullptr;
  std::vector<MatteView> mattes;  // one per view (unusable where none)
  std::vector<int> usable;        // indices of usable mattes
};

// Whether `point` is in the matte-consistent region: seen by at least
// kMinSeeingViews matte views (or all, if fewer) and covered by at least
// `consensus` of those that see it. Views that do not see it (it projects
// outside the photo) do not count: a trunk cut by the photos' bottom edge
// is not cut off in 3D.
bool Consistent(const Analysis& analysis, const Eigen::Vector3d& point, double consensus) {
  int seen = 0, covered = 0;
  for (const int view_idx : analysis.usable) {
    Eigen::Vector2d pixel;
    if (!analysis.cameras->Project(view_idx, point, &pixel)) continue;
    const Camera& camera = analysis.cameras->CameraOf(view_idx);
    if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= camera.width() ||
        pixel.y() >= camera.height()) {
      continue;
    }
    ++seen;
    if (analysis.mattes[view_idx].Covers(pixel)) ++covered;
  }
  const int min_seen = std::min<int>(kMinSeeingViews, analysis.usable.size());
  return seen >= min_seen && seen > 0 && covered >= consensus * seen;
}

// World length of one working matte pixel near `point` (median over views).
double PixelFootprint(const Analysis& analysis, const Eigen::Vector3d& point,
                      const WorldFrameOptions& options) {
  std::vector<double> footprints;
  for (const int view_idx : analysis.usable) {
    const View& view = analysis.cameras->views[view_idx];
    const Camera& camera = analysis.cameras->CameraOf(view);
    const double camera_pixels =
        static_cast<double>(std::max(camera.width(), camera.height())) / options.matte_working_size;
    const double depth =
        camera.IsOrthographic() ? 1.0 : std::abs((view.cam_from_world * point).z());
    footprints.push_back(std::max(1.0, camera_pixels) * depth / camera.FocalLengthX());
  }
  std::nth_element(footprints.begin(), footprints.begin() + footprints.size() / 2,
                   footprints.end());
  return footprints[footprints.size() / 2];
}

// Slides `start` along `up` to the bottom of the matte-consistent region
// (first to the nearest consistent point if `start` is not one). Returns the
// offset along up, or nullopt if no consistent point lies within reach.
std::optional<double> LowestConsistent(const Analysis& analysis, const Eigen::Vector3d& start,
                                       const Eigen::Vector3d& up,
                                       const WorldFrameOptions& options) {
  const double step = PixelFootprint(analysis, start, options);
  // Far enough to cross any photo (in working pixels).
  const int max_steps = 4 * options.matte_working_size;
  std::optional<double> found;
  for (int k = 0; k <= max_steps && !found; ++k) {
    for (const double t : {-k * step, k * step}) {
      if (Consistent(analysis, start + t * up, options.consensus)) {
        found = t;
        break;
      }
    }
  }
  if (!found) return std::nullopt;
  double t = *found;
  for (int k = 0; k < max_steps && Consistent(analysis, start + (t - step) * up, options.consensus);
       ++k) {
    t -= step;
  }
  return t;
}

// The point the cameras' optical axes pass closest to.
std::optional<Eigen::Vector3d> OpticalAxesMeet(const ImageSet& cameras) {
  std::vector<Ray3d> axes;
  for (const View& view : cameras.views) {
    Ray3d axis;
    axis.origin = view.ProjectionCenter();
    axis.direction = view.ViewingDirection();
    axes.push_back(axis);
  }
  return Triangulate(axes);
}

struct BaseEstimate {
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  double height = 0.0;  // input-frame units; 0 = unknown
  std::string source;
};

// Base and top from the mattes (see the header).
void BaseFromMattes(const Analysis& analysis, const Eigen::Vector3d& up,
                    const WorldFrameOptions& options, BaseEstimate* estimate) {
  std::vector<Ray3d> bottom_rays, top_rays;
  for (const int view_idx : analysis.usable) {
    bottom_rays.push_back(
        analysis.cameras->RayThroughPixel(view_idx, analysis.mattes[view_idx].bottom()));
    top_rays.push_back(
        analysis.cameras->RayThroughPixel(view_idx, analysis.mattes[view_idx].top()));
  }
  const std::optional<Eigen::Vector3d> bottom = Triangulate(bottom_rays);
  if (!bottom) return;
  const std::string views = std::to_string(analysis.usable.size()) + " views";
  const std::optional<double> slide = LowestConsistent(analysis, *bottom, up, options);
  estimate->base = *bottom + slide.value_or(0.0) * up;
  estimate->source =
      slide ? "mattes (" + views + ")"
            : "mattes' lowest points (" + views + "; no consistent region found along up)";
  if (const std::optional<Eigen::Vector3d> top = Triangulate(top_rays)) {
    estimate->height = std::max(0.0, (*top - estimate->base).dot(up));
  }
}

BaseEstimate EstimateBase(const Analysis& analysis, const Eigen::Vector3d& up,
                          const WorldFrameOptions& options) {
  BaseEstimate estimate;
  const bool from_mattes = analysis.usable.size() >= 2;
  if (from_mattes) BaseFromMattes(analysis, up, options, &estimate);
  if (options.base == "keep") {
    estimate.base = Eigen::Vector3d::Zero();
    estimate.source = "kept (origin)";
  } else if (estimate.source.empty()) {
    if (const auto meet = OpticalAxesMeet(*analysis.cameras)) {
      estimate.base = *meet;
      estimate.source = "optical axes' meeting point (no usable mattes: not the trunk's bottom)";
    } else {
      estimate.source = "kept (origin; no usable mattes, optical axes parallel)";
    }
  }
  return estimate;
}

Analysis AnalyseMattes(const ImageSet& cameras, const std::vector<FloatImage>& mattes,
                       const Eigen::Vector3d& up, const WorldFrameOptions& options) {
  SYLVA_CHECK_INPUT(mattes.empty() || static_cast<int>(mattes.size()) == cameras.NumViews(),
                    "mattes")
      << mattes.size() << " mattes for " << cameras.NumViews() << " views";
  Analysis analysis;
  analysis.cameras = &cameras;
  const double scene_scale = SceneScale(cameras);
  for (int i = 0; i < cameras.NumViews(); ++i) {
    static const FloatImage kNone;
    analysis.mattes.emplace_back(cameras, i, mattes.empty() ? kNone : mattes[i], up, scene_scale,
                                 options);
    if (analysis.mattes.back().usable()) analysis.usable.push_back(i);
  }
  return analysis;
}

// Rotation about +Z that turns the first view's horizontal viewing direction
// to +Y, so "auto" frames have a reproducible heading.
Eigen::Quaterniond HeadingFromFirstView(const ImageSet& cameras,
                                        const Eigen::Quaterniond& upright) {
  const Eigen::Vector3d looking = upright * cameras.views.front().ViewingDirection();
  if (std::hypot(looking.x(), looking.y()) < 1e-6) return Eigen::Quaterniond::Identity();
  const double angle = std::atan2(looking.x(), looking.y());  // from +Y towards +X
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

}  // namespace

std::string WorldFrame::BriefReport() const {
  std::ostringstream text;
  text.precision(4);
  text << "up from " << up_source << ", base from " << base_source << ", height ";
  if (tree_height > 0) {
    text << tree_height << " " << units;
  } else {
    text << "unknown";
  }
  text << ", scale " << world_from_model.scale;
  return text.str();
}

WorldFrame EstimateWorldFrame(const ImageSet& cameras, const std::vector<FloatImage>& mattes,
                              const WorldFrameOptions& options) {
  options.Check();
  cameras.Check("cameras");
  const UpEstimate up = EstimateUp(cameras, options);
  const Analysis analysis = AnalyseMattes(cameras, mattes, up.up, options);
  const BaseEstimate base = EstimateBase(analysis, up.up, options);

  WorldFrame frame;
  frame.up_in_model = up.up;
  frame.up_source = up.source;
  frame.base_in_model = base.base;
  frame.base_source = base.source;
  double scale = 1.0;
  if (options.known_height > 0) {
    SYLVA_CHECK_INPUT(base.height > 0, "WorldFrame.known_height")
        << "the tree's height could not be measured to scale it (it needs mattes of at least 2 "
           "views; base: "
        << base.source << ")";
    scale = options.known_height / base.height;
    frame.units = options.units;
  }
  frame.tree_height = scale * base.height;

  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  if (options.up == "auto") {
    rotation = Eigen::Quaterniond::FromTwoVectors(up.up, Eigen::Vector3d::UnitZ());
    rotation = HeadingFromFirstView(cameras, rotation) * rotation;
  } else if (options.up != "keep") {
    rotation = AxisToZ(up.up);
  }
  frame.world_from_model = Sim3d(scale, rotation, -(scale * (rotation * base.base)));
  return frame;
}

ImageSet TransformCameras(const ImageSet& cameras, const WorldFrame& frame) {
  const Sim3d& world_from_model = frame.world_from_model;
  ImageSet moved = cameras;
  for (View& view : moved.views) {
    view.cam_from_world = world_from_model.TransformPose(view.cam_from_world);
  }
  for (Point3D& point : moved.points) point.position = world_from_model * point.position;
  for (auto& [camera_id, camera] : moved.cameras) {
    if (!camera.IsOrthographic()) continue;
    std::vector<double> params = camera.params();
    params[0] /= world_from_model.scale;
    params[1] /= world_from_model.scale;
    camera = Camera(camera.model(), camera.width(), camera.height(), params);
  }
  return moved;
}

}  // namespace sylva
