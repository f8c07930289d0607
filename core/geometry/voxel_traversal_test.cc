#include "core/geometry/voxel_traversal.h"

#include <gtest/gtest.h>

#include <map>

#include "core/util/random.h"

namespace sylva {
namespace {

// Brute force: sample the clipped segment densely and accumulate the length
// falling in each voxel.
std::map<int64_t, double> BruteForce(const VoxelBlock& block, const Ray3d& ray) {
  std::map<int64_t, double> lengths;
  double t0, t1;
  if (!ClipRayToBox(ray, block.WorldBox(), &t0, &t1)) return lengths;
  const int samples = 200000;
  const double dt = (t1 - t0) / samples;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d p = ray.origin + ray.direction * (t0 + (s + 0.5) * dt);
    const Eigen::Vector3d rel = (p - block.lower_corner) / block.voxel_size;
    Eigen::Vector3i ijk = rel.array().floor().cast<int>();
    ijk = ijk.cwiseMax(0).cwiseMin(block.dims - Eigen::Vector3i::Ones());
    lengths[block.LinearIndex(ijk)] += dt;
  }
  return lengths;
}

TEST(VoxelTraversalTest, MatchesBruteForceOnRandomRays) {
  VoxelBlock block;
  block.lower_corner = Eigen::Vector3d(-1.0, 0.5, 2.0);
  block.voxel_size = 0.25;
  block.dims = Eigen::Vector3i(7, 5, 9);
  RandomEngine rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    Ray3d ray;
    ray.origin = Eigen::Vector3d(rng.Uniform(-4, 4), rng.Uniform(-3, 4), rng.Uniform(-2, 8));
    ray.direction = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    ray.t_min = (trial % 2 == 0) ? 0.0 : -1e30;
    std::map<int64_t, double> exact;
    double total = 0.0;
    int previous = -1;
    TraverseVoxels(block, ray, [&](int64_t index, double length) {
      EXPECT_EQ(exact.count(index), 0u) << "voxel visited twice";
      EXPECT_NE(index, previous);
      exact[index] = length;
      total += length;
      previous = static_cast<int>(index);
    });
    const std::map<int64_t, double> brute = BruteForce(block, ray);
    double t0, t1;
    if (ClipRayToBox(ray, block.WorldBox(), &t0, &t1)) {
      EXPECT_NEAR(total, t1 - t0, 1e-9);
    }
    // Every voxel the samples found with a non-negligible length is visited
    // with the same length (up to the sampling resolution).
    const double tolerance = 1e-3;
    for (const auto& [index, length] : brute) {
      if (length < tolerance) continue;
      ASSERT_EQ(exact.count(index), 1u) << "missed voxel " << index;
      EXPECT_NEAR(exact[index], length, tolerance);
    }
    for (const auto& [index, length] : exact) {
      if (length > tolerance) {
        EXPECT_EQ(brute.count(index), 1u) << "extra voxel " << index;
      }
    }
  }
}

TEST(VoxelTraversalTest, AxisAlignedRayThroughCentres) {
  VoxelBlock block;
  block.dims = Eigen::Vector3i(4, 4, 4);
  Ray3d ray;
  ray.origin = Eigen::Vector3d(-1, 1.5, 2.5);
  ray.direction = Eigen::Vector3d::UnitX();
  std::vector<int64_t> visited;
  TraverseVoxels(block, ray, [&](int64_t index, double length) {
    EXPECT_NEAR(length, 1.0, 1e-12);
    visited.push_back(index);
  });
  ASSERT_EQ(visited.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(visited[i], block.LinearIndex({i, 1, 2}));
}

TEST(VoxelTraversalTest, MissingRayVisitsNothing) {
  VoxelBlock block;
  block.dims = Eigen::Vector3i(2, 2, 2);
  Ray3d ray;
  ray.origin = Eigen::Vector3d(5, 5, 5);
  ray.direction = Eigen::Vector3d::UnitX();
  EXPECT_EQ(TraverseVoxels(block, ray, [](int64_t, double) {}), 0);
  // A ray starting past the box (t_min = 0) sees nothing behind it.
  ray.origin = Eigen::Vector3d(3, 1, 1);
  EXPECT_EQ(TraverseVoxels(block, ray, [](int64_t, double) {}), 0);
}

}  // namespace
}  // namespace sylva
