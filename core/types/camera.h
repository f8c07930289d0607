// Camera intrinsics: orthographic, and pinhole with COLMAP's camera models.
//
// Conventions follow COLMAP exactly, so COLMAP models are read without
// conversion:
//   - camera frame: x right, y down, z forward (viewing direction);
//   - image coordinates in pixels, the centre of pixel (col i, row j) at
//     (i + 0.5, j + 0.5), so the image spans [0, width] x [0, height];
//   - parameters in COLMAP's order:
//       SIMPLE_PINHOLE  f, cx, cy
//       PINHOLE         fx, fy, cx, cy
//       SIMPLE_RADIAL   f, cx, cy, k
//       RADIAL          f, cx, cy, k1, k2
//       OPENCV          fx, fy, cx, cy, k1, k2, p1, p2
//       ORTHOGRAPHIC    fx, fy, cx, cy   (sylva's own; fx, fy in pixels per world unit)
// An orthographic camera maps point_in_cam (x, y, z) to (fx x + cx, fy y + cy)
// regardless of z; its pixel rays are full lines along +z.
#ifndef SYLVA_CORE_TYPES_CAMERA_H_
#define SYLVA_CORE_TYPES_CAMERA_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/geometry/rigid3.h"

namespace sylva {

enum class CameraModel {
  kOrthographic,
  kSimplePinhole,
  kPinhole,
  kSimpleRadial,
  kRadial,
  kOpenCV,
};

// COLMAP's name ("SIMPLE_RADIAL") of a model, and back. ParseCameraModel
// throws InputError naming `source` for an unknown name.
std::string CameraModelName(CameraModel model);
CameraModel ParseCameraModel(const std::string& name, const std::string& source);
int CameraModelNumParams(CameraModel model);
// COLMAP's numeric model id (for binary models); -1 for ORTHOGRAPHIC.
int CameraModelColmapId(CameraModel model);
CameraModel CameraModelFromColmapId(int id, const std::string& source);

class Camera {
 public:
  Camera() = default;
  // Throws InputError (with an empty source) if `params` does not have the
  // model's parameter count.
  Camera(CameraModel model, int width, int height, std::vector<double> params);

  // Convenience constructors.
  static Camera Orthographic(int width, int height, double pixels_per_unit);
  static Camera Pinhole(int width, int height, double focal_length_px);

  CameraModel model() const { return model_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<double>& params() const { return params_; }
  bool IsOrthographic() const { return model_ == CameraModel::kOrthographic; }
  bool HasDistortion() const;

  double FocalLengthX() const;
  double FocalLengthY() const;
  Eigen::Vector2d PrincipalPoint() const;
  // World units one pixel spans at a camera-frame point (mean of both focal
  // lengths; distortion ignored): depth / focal, or 1 / focal if orthographic.
  double WorldPerPixel(const Eigen::Vector3d& point_in_cam) const;

  // The same camera for an image resized by `scale` (e.g. 1/4 for a 4x
  // box-downsampled image) to new_width x new_height: focal lengths and
  // principal point scale (pixel edges map onto pixel edges); distortion,
  // which acts on normalized coordinates, is unchanged.
  Camera Scaled(double scale, int new_width, int new_height) const;

  // Throws InputError (naming `source`) if the parameter count, image size or
  // focal lengths are invalid.
  void Check(const std::string& source) const;

  // Pixel position of a point in the camera frame. For pinhole models the
  // point must be in front of the camera (z > 0); check with IsInFront().
  Eigen::Vector2d ImgFromCam(const Eigen::Vector3d& point_in_cam) const;
  bool IsInFront(const Eigen::Vector3d& point_in_cam) const;

  // For pinhole models, the normalized undistorted coordinates (x/z, y/z) of
  // the pixel (inverting the distortion with Newton's method); for the
  // orthographic model, the (x, y) position in the camera frame.
  Eigen::Vector2d CamFromImg(const Eigen::Vector2d& point_in_image) const;

  // The ray through a pixel, in the camera frame (unit direction).
  Ray3d CamRayFromImg(const Eigen::Vector2d& point_in_image) const;
  // A pinhole model's ray through the normalized point `xy` (CamFromImg's
  // result): CamRayFromImg's ray, for callers that keep the points.
  static Ray3d PerspectiveRay(const Eigen::Vector2d& xy);

  // Distortion applied to normalized coordinates (identity for models without).
  // Undistort inverts it by Newton's method; where the distortion is not
  // invertible (far outside the image for strong distortion) the result is
  // the last iterate, as in COLMAP.
  Eigen::Vector2d Distort(const Eigen::Vector2d& undistorted) const;
  Eigen::Vector2d Undistort(const Eigen::Vector2d& distorted) const;

 private:
  // Offset added by distortion at normalized point (u, v), and its Jacobian.
  Eigen::Vector2d DistortionOffset(const Eigen::Vector2d& uv, Eigen::Matrix2d* jacobian) const;

  CameraModel model_ = CameraModel::kPinhole;
  int width_ = 0;
  int height_ = 0;
  std::vector<double> params_ = {1, 1, 0, 0};
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_CAMERA_H_
