#include "core/geometry/rigid3.h"

#include "core/util/check.h"

namespace sylva {

Rigid3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up) {
  const Eigen::Vector3d z_axis = (target - center).normalized();
  SYLVA_CHECK(z_axis.allFinite()) << "camera centre and target coincide";
  Eigen::Vector3d x_axis = z_axis.cross(up);
  SYLVA_CHECK(x_axis.norm() > 1e-9) << "viewing direction is parallel to the up vector";
  x_axis.normalize();
  const Eigen::Vector3d y_axis = z_axis.cross(x_axis);
  Eigen::Matrix3d world_from_cam_rotation;
  world_from_cam_rotation << x_axis, y_axis, z_axis;
  const Eigen::Quaterniond cam_from_world_rotation(world_from_cam_rotation.transpose());
  return Rigid3d(cam_from_world_rotation, -(cam_from_world_rotation * center));
}

}  // namespace sylva
