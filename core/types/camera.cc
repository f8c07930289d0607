#include "core/types/camera.h"

#include <cmath>
#include <limits>

#include "core/util/check.h"

namespace sylva {
namespace {

struct ModelInfo {
  CameraModel model;
  const char* name;
  int num_params;
  int colmap_id;
};

constexpr ModelInfo kModels[] = {
    {CameraModel::kOrthographic, "ORTHOGRAPHIC", 4, -1},
    {CameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3, 0},
    {CameraModel::kPinhole, "PINHOLE", 4, 1},
    {CameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4, 2},
    {CameraModel::kRadial, "RADIAL", 5, 3},
    {CameraModel::kOpenCV, "OPENCV", 8, 4},
};

const ModelInfo& Info(CameraModel model) {
  for (const ModelInfo& info : kModels) {
    if (info.model == model) return info;
  }
  SYLVA_CHECK(false) << "unknown camera model";
  return kModels[0];
}

bool HasSingleFocalLength(CameraModel model) {
  return model == CameraModel::kSimplePinhole || model == CameraModel::kSimpleRadial ||
         model == CameraModel::kRadial;
}

// Newton's method for undistortion: iterations and convergence tolerance on
// the normalized-coordinate update (COLMAP uses similar values).
constexpr int kUndistortMaxIterations = 100;
constexpr double kUndistortTolerance = 1e-12;

}  // namespace

std::string CameraModelName(CameraModel model) { return Info(model).name; }

CameraModel ParseCameraModel(const std::string& name, const std::string& source) {
  for (const ModelInfo& info : kModels) {
    if (name == info.name) return info.model;
  }
  SYLVA_INPUT_ERROR(source) << "unsupported camera model '" << name
                            << "' (supported: ORTHOGRAPHIC, SIMPLE_PINHOLE, PINHOLE, "
                               "SIMPLE_RADIAL, RADIAL, OPENCV)";
  return CameraModel::kPinhole;
}

int CameraModelNumParams(CameraModel model) { return Info(model).num_params; }
int CameraModelColmapId(CameraModel model) { return Info(model).colmap_id; }

CameraModel CameraModelFromColmapId(int id, const std::string& source) {
  for (const ModelInfo& info : kModels) {
    if (info.colmap_id == id && id >= 0) return info.model;
  }
  SYLVA_INPUT_ERROR(source) << "unsupported COLMAP camera model id " << id
                            << " (supported: 0-4: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, "
                               "RADIAL, OPENCV)";
  return CameraModel::kPinhole;
}

Camera::Camera(CameraModel model, int width, int height, std::vector<double> params)
    : model_(model), width_(width), height_(height), params_(std::move(params)) {
  // Every accessor indexes params_ by the model's layout, so a wrong count is
  // refused here; readers re-raise this at the offending file location.
  SYLVA_CHECK_INPUT(static_cast<int>(params_.size()) == CameraModelNumParams(model_), "")
      << CameraModelName(model_) << " camera needs " << CameraModelNumParams(model_)
      << " parameters, got " << params_.size();
}

Camera Camera::Orthographic(int width, int height, double pixels_per_unit) {
  return Camera(CameraModel::kOrthographic, width, height,
                {pixels_per_unit, pixels_per_unit, 0.5 * width, 0.5 * height});
}

Camera Camera::Pinhole(int width, int height, double focal_length_px) {
  return Camera(CameraModel::kPinhole, width, height,
                {focal_length_px, focal_length_px, 0.5 * width, 0.5 * height});
}

Camera Camera::Scaled(double scale, int new_width, int new_height) const {
  std::vector<double> params = params_;
  const int intrinsics = HasSingleFocalLength(model_) ? 3 : 4;  // f (or fx, fy), cx, cy
  for (int i = 0; i < intrinsics; ++i) params[i] *= scale;
  return Camera(model_, new_width, new_height, std::move(params));
}

bool Camera::HasDistortion() const {
  switch (model_) {
    case CameraModel::kSimpleRadial:
    case CameraModel::kRadial:
    case CameraModel::kOpenCV:
      return true;
    default:
      return false;
  }
}

double Camera::FocalLengthX() const { return params_[0]; }
double Camera::FocalLengthY() const {
  return HasSingleFocalLength(model_) ? params_[0] : params_[1];
}
double Camera::WorldPerPixel(const Eigen::Vector3d& point_in_cam) const {
  const double focal = 0.5 * (FocalLengthX() + FocalLengthY());
  return IsOrthographic() ? 1.0 / focal : point_in_cam.z() / focal;
}

Eigen::Vector2d Camera::PrincipalPoint() const {
  const int offset = HasSingleFocalLength(model_) ? 1 : 2;
  return Eigen::Vector2d(params_[offset], params_[offset + 1]);
}

void Camera::Check(const std::string& source) const {
  SYLVA_CHECK_INPUT(static_cast<int>(params_.size()) == CameraModelNumParams(model_), source)
      << CameraModelName(model_) << " camera needs " << CameraModelNumParams(model_)
      << " parameters, got " << params_.size();
  SYLVA_CHECK_INPUT(width_ > 0 && height_ > 0, source)
      << "camera image size must be positive, got " << width_ << "x" << height_;
  for (double p : params_) {
    SYLVA_CHECK_INPUT(std::isfinite(p), source) << "camera parameter is not finite";
  }
  SYLVA_CHECK_INPUT(FocalLengthX() > 0 && FocalLengthY() > 0, source)
      << "focal lengths must be positive, got " << FocalLengthX() << ", " << FocalLengthY();
}

bool Camera::IsInFront(const Eigen::Vector3d& point_in_cam) const {
  return IsOrthographic() || point_in_cam.z() > std::numeric_limits<double>::epsilon();
}

Eigen::Vector2d Camera::DistortionOffset(const Eigen::Vector2d& uv,
                                         Eigen::Matrix2d* jacobian) const {
  const double u = uv.x(), v = uv.y();
  const double u2 = u * u, v2 = v * v, uv_prod = u * v, r2 = u2 + v2;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;
  switch (model_) {
    case CameraModel::kSimpleRadial:
      k1 = params_[3];
      break;
    case CameraModel::kRadial:
      k1 = params_[3];
      k2 = params_[4];
      break;
    case CameraModel::kOpenCV:
      k1 = params_[4];
      k2 = params_[5];
      p1 = params_[6];
      p2 = params_[7];
      break;
    default:
      if (jacobian) jacobian->setZero();
      return Eigen::Vector2d::Zero();
  }
  // COLMAP's OpenCV-style distortion; the radial-only models are its special cases.
  const double radial = k1 * r2 + k2 * r2 * r2;
  const Eigen::Vector2d offset(u * radial + 2 * p1 * uv_prod + p2 * (r2 + 2 * u2),
                               v * radial + 2 * p2 * uv_prod + p1 * (r2 + 2 * v2));
  if (jacobian) {
    const double d_radial_d_r2 = k1 + 2 * k2 * r2;
    // d r2 / du = 2u, d r2 / dv = 2v.
    (*jacobian)(0, 0) = radial + u * d_radial_d_r2 * 2 * u + 2 * p1 * v + p2 * 6 * u;
    (*jacobian)(0, 1) = u * d_radial_d_r2 * 2 * v + 2 * p1 * u + p2 * 2 * v;
    (*jacobian)(1, 0) = v * d_radial_d_r2 * 2 * u + 2 * p2 * v + p1 * 2 * u;
    (*jacobian)(1, 1) = radial + v * d_radial_d_r2 * 2 * v + 2 * p2 * u + p1 * 6 * v;
  }
  return offset;
}

Eigen::Vector2d Camera::Distort(const Eigen::Vector2d& undistorted) const {
  if (!HasDistortion()) return undistorted;  // the same as adding a zero offset
  return undistorted + DistortionOffset(undistorted, nullptr);
}

Eigen::Vector2d Camera::Undistort(const Eigen::Vector2d& distorted) const {
  if (!HasDistortion()) return distorted;
  // Solve Distort(x) = distorted by Newton's method, starting at `distorted`.
  Eigen::Vector2d x = distorted;
  for (int iteration = 0; iteration < kUndistortMaxIterations; ++iteration) {
    Eigen::Matrix2d jacobian;
    const Eigen::Vector2d residual = x + DistortionOffset(x, &jacobian) - distorted;
    jacobian += Eigen::Matrix2d::Identity();
    // The 2 x 2 system by Cramer's rule: a tenth of an LU's cost, per pixel
    // ray of every distorted camera (the Jacobian is near the identity).
    const double det = jacobian(0, 0) * jacobian(1, 1) - jacobian(0, 1) * jacobian(1, 0);
    const Eigen::Vector2d step(
        (jacobian(1, 1) * residual.x() - jacobian(0, 1) * residual.y()) / det,
        (jacobian(0, 0) * residual.y() - jacobian(1, 0) * residual.x()) / det);
    if (!step.allFinite()) break;
    x -= step;
    if (step.squaredNorm() < kUndistortTolerance * kUndistortTolerance * (1 + x.squaredNorm())) {
      break;
    }
  }
  return x;
}

Eigen::Vector2d Camera::ImgFromCam(const Eigen::Vector3d& point_in_cam) const {
  Eigen::Vector2d normalized;
  if (IsOrthographic()) {
    normalized = point_in_cam.head<2>();
  } else {
    normalized = Distort(point_in_cam.head<2>() / point_in_cam.z());
  }
  const Eigen::Vector2d principal_point = PrincipalPoint();
  return Eigen::Vector2d(FocalLengthX() * normalized.x() + principal_point.x(),
                         FocalLengthY() * normalized.y() + principal_point.y());
}

Eigen::Vector2d Camera::CamFromImg(const Eigen::Vector2d& point_in_image) const {
  const Eigen::Vector2d principal_point = PrincipalPoint();
  const Eigen::Vector2d distorted((point_in_image.x() - principal_point.x()) / FocalLengthX(),
                                  (point_in_image.y() - principal_point.y()) / FocalLengthY());
  return Undistort(distorted);
}

Ray3d Camera::CamRayFromImg(const Eigen::Vector2d& point_in_image) const {
  const Eigen::Vector2d xy = CamFromImg(point_in_image);
  Ray3d ray;
  if (IsOrthographic()) {
    ray.origin = Eigen::Vector3d(xy.x(), xy.y(), 0.0);
    ray.direction = Eigen::Vector3d::UnitZ();
    ray.t_min = -std::numeric_limits<double>::infinity();
  } else {
    ray = PerspectiveRay(xy);
  }
  return ray;
}

Ray3d Camera::PerspectiveRay(const Eigen::Vector2d& xy) {
  Ray3d ray;
  ray.origin = Eigen::Vector3d::Zero();
  ray.direction = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  ray.t_min = 0.0;
  return ray;
}

}  // namespace sylva
