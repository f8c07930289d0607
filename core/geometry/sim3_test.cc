#include "core/geometry/sim3.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

Eigen::Quaterniond RandomRotation(RandomEngine* random) {
  return Eigen::Quaterniond(random->Normal(), random->Normal(), random->Normal(), random->Normal())
      .normalized();
}

Eigen::Vector3d RandomPoint(RandomEngine* random, double extent) {
  return {random->Uniform(-extent, extent), random->Uniform(-extent, extent),
          random->Uniform(-extent, extent)};
}

Sim3d RandomSim3(RandomEngine* random) {
  return Sim3d(std::exp(random->Uniform(-3, 3)), RandomRotation(random), RandomPoint(random, 100));
}

TEST(Sim3Test, ComposesAndInverts) {
  RandomEngine random(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Sim3d a = RandomSim3(&random);
    const Sim3d b = RandomSim3(&random);
    const Eigen::Vector3d point = RandomPoint(&random, 10);
    EXPECT_LT(((a * b) * point - a * (b * point)).norm(), 1e-9 * (1 + (a * (b * point)).norm()));
    EXPECT_LT((a.Inverse() * (a * point) - point).norm(), 1e-9 * (1 + point.norm()));
    const Eigen::Matrix<double, 3, 4> matrix = a.ToMatrix();
    EXPECT_LT((matrix.leftCols<3>() * point + matrix.col(3) - a * point).norm(),
              1e-9 * (1 + (a * point).norm()));
  }
}

// A moved camera sees every moved point in the same direction (and, for the
// scaled camera frame, at `scale` times the depth).
TEST(Sim3Test, TransformPoseKeepsProjections) {
  RandomEngine random(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Sim3d target_from_source = RandomSim3(&random);
    const Rigid3d cam_from_source(RandomRotation(&random), RandomPoint(&random, 5));
    const Rigid3d cam_from_target = target_from_source.TransformPose(cam_from_source);
    const Eigen::Vector3d point = RandomPoint(&random, 10);
    const Eigen::Vector3d in_cam = cam_from_source * point;
    const Eigen::Vector3d in_cam_after = cam_from_target * (target_from_source * point);
    EXPECT_LT((in_cam_after - target_from_source.scale * in_cam).norm(),
              1e-9 * (1 + in_cam_after.norm()));
  }
}

TEST(Sim3Test, EstimateRecoversKnownSimilarity) {
  RandomEngine random(3);
  const Sim3d truth = RandomSim3(&random);
  std::vector<Eigen::Vector3d> source, target;
  for (int i = 0; i < 30; ++i) {
    source.push_back(RandomPoint(&random, 2));
    target.push_back(truth * source.back());
  }
  const Sim3d estimate = EstimateSim3(source, target);
  EXPECT_NEAR(estimate.scale, truth.scale, 1e-9 * truth.scale);
  EXPECT_LT(estimate.rotation.angularDistance(truth.rotation), 1e-9);
  EXPECT_LT((estimate.translation - truth.translation).norm(), 1e-7);

  // Noise: the estimate degrades gracefully.
  for (Eigen::Vector3d& point : target) point += 0.01 * truth.scale * RandomPoint(&random, 1);
  const Sim3d noisy = EstimateSim3(source, target);
  EXPECT_NEAR(noisy.scale / truth.scale, 1.0, 0.01);
  EXPECT_LT(noisy.rotation.angularDistance(truth.rotation), 0.01);
}

TEST(Sim3Test, EstimateRejectsDegenerateInput) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_THROW(EstimateSim3(line, line), Error);
  EXPECT_THROW(EstimateSim3({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}), Error);
  EXPECT_THROW(EstimateSim3(line, {{0, 0, 0}}), Error);
}

}  // namespace
}  // namespace sylva
