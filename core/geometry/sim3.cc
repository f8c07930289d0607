#include "core/geometry/sim3.h"

#include <Eigen/SVD>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Points closer to their best-fit line than this fraction of their spread
// are collinear: the rotation about that line is undetermined.
constexpr double kMinRelativeSpread = 1e-9;

}  // namespace

Eigen::Matrix<double, 3, 4> Sim3d::ToMatrix() const {
  Eigen::Matrix<double, 3, 4> matrix;
  matrix.leftCols<3>() = scale * rotation.toRotationMatrix();
  matrix.col(3) = translation;
  return matrix;
}

Rigid3d Sim3d::TransformPose(const Rigid3d& cam_from_source) const {
  // x_cam = R_c x_s + t_c and x_s = R^T (x_t - t) / s, so
  // s x_cam = R_c R^T x_t + (s t_c - R_c R^T t).
  const Eigen::Quaterniond cam_from_target_rotation = cam_from_source.rotation * rotation.inverse();
  return Rigid3d(cam_from_target_rotation,
                 scale * cam_from_source.translation - cam_from_target_rotation * translation);
}

Sim3d EstimateSim3(const std::vector<Eigen::Vector3d>& source,
                   const std::vector<Eigen::Vector3d>& target) {
  SYLVA_CHECK(source.size() == target.size())
      << source.size() << " source points but " << target.size() << " target points";
  SYLVA_CHECK(source.size() >= 3) << "a similarity needs at least 3 point pairs";
  const int n = static_cast<int>(source.size());
  Eigen::Matrix3Xd source_matrix(3, n), target_matrix(3, n);
  for (int i = 0; i < n; ++i) {
    source_matrix.col(i) = source[i];
    target_matrix.col(i) = target[i];
  }
  // Both point sets must span a plane, or the rotation is undetermined.
  for (const Eigen::Matrix3Xd* points : {&source_matrix, &target_matrix}) {
    const Eigen::Matrix3Xd centred = points->colwise() - points->rowwise().mean();
    const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
    SYLVA_CHECK(singular(1) > kMinRelativeSpread * singular(0) && singular(0) > 0)
        << "the points are collinear or coincide; a similarity is undetermined";
  }
  const Eigen::Matrix4d matrix = Eigen::umeyama(source_matrix, target_matrix, true);
  const Eigen::Matrix3d scaled_rotation = matrix.topLeftCorner<3, 3>();
  const double scale = std::cbrt(scaled_rotation.determinant());
  return Sim3d(scale, Eigen::Quaterniond(scaled_rotation / scale), matrix.topRightCorner<3, 1>());
}

}  // namespace sylva
