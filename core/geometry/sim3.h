// Similarity transforms in 3D (rotation, uniform scale, translation), named
// target_from_source like Rigid3d:
//   point_in_target = scale * (rotation * point_in_source) + translation
// Used to move a registration into sylva's world frame (up = +Z, tree base at
// the origin, metres when known) and to compare two registrations of the same
// photos, which agree only up to a similarity (structure from motion fixes
// neither the frame nor the scale).
#ifndef SYLVA_CORE_GEOMETRY_SIM3_H_
#define SYLVA_CORE_GEOMETRY_SIM3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/geometry/rigid3.h"

namespace sylva {

struct Sim3d {
  double scale = 1.0;  // > 0
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Sim3d() = default;
  Sim3d(double scale, const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation)
      : scale(scale), rotation(rotation.normalized()), translation(translation) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return scale * (rotation * point) + translation;
  }
  // (this * other) * p == this * (other * p).
  Sim3d operator*(const Sim3d& other) const {
    return Sim3d(scale * other.scale, rotation * other.rotation,
                 scale * (rotation * other.translation) + translation);
  }
  Sim3d Inverse() const {
    const Eigen::Quaterniond inverse_rotation = rotation.inverse();
    return Sim3d(1.0 / scale, inverse_rotation, -(inverse_rotation * translation) / scale);
  }
  Eigen::Matrix<double, 3, 4> ToMatrix() const;

  // A camera's pose after the world is moved by this transform. Given
  // cam_from_source, returns cam_from_target such that a source point and
  // its image (this * point) have the same camera-frame direction; camera
  // coordinates are multiplied by `scale`, so pinhole projections are
  // unchanged and orthographic cameras need their pixels per world unit
  // divided by `scale`.
  Rigid3d TransformPose(const Rigid3d& cam_from_source) const;
};

// The least-squares similarity mapping `source` points onto `target` points
// (Umeyama 1991): minimises sum |target_i - sim * source_i|^2. Needs at least
// 3 pairs that are not collinear; throws Error otherwise (a caller's bug, or
// InputError-worthy data the caller should have checked).
Sim3d EstimateSim3(const std::vector<Eigen::Vector3d>& source,
                   const std::vector<Eigen::Vector3d>& target);

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_SIM3_H_
