// Rigid transforms in 3D, named target_from_source (COLMAP's convention):
//   point_in_cam = cam_from_world * point_in_world
#ifndef SYLVA_CORE_GEOMETRY_RIGID3_H_
#define SYLVA_CORE_GEOMETRY_RIGID3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sylva {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation)
      : rotation(rotation.normalized()), translation(translation) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
  Rigid3d operator*(const Rigid3d& other) const {
    return Rigid3d(rotation * other.rotation, rotation * other.translation + translation);
  }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inverse_rotation = rotation.inverse();
    return Rigid3d(inverse_rotation, -(inverse_rotation * translation));
  }
  Eigen::Matrix<double, 3, 4> ToMatrix() const {
    Eigen::Matrix<double, 3, 4> matrix;
    matrix.leftCols<3>() = rotation.toRotationMatrix();
    matrix.col(3) = translation;
    return matrix;
  }
};

// The camera pose looking from `center` towards `target`, with the image's
// up direction (-y in camera frame) as close to `up` as possible. Camera axes
// follow COLMAP: x right, y down, z forward. Returns cam_from_world.
Rigid3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up);

// A ray origin + t * direction for t in [t_min, +inf). Orthographic cameras
// produce full lines (t_min = -inf) because their image plane has no position
// along the viewing axis.
struct Ray3d {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit length
  double t_min = 0.0;
};

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_RIGID3_H_
