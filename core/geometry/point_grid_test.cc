#include "core/geometry/point_grid.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/util/random.h"

namespace sylva {
namespace {

TEST(PointGridTest, NearestMatchesBruteForce) {
  RandomEngine rng(4);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 500; ++i) points.emplace_back(rng.Normal(), rng.Normal(), 3 * rng.Uniform());
  const PointGrid grid(points);
  const double inf = std::numeric_limits<double>::infinity();
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d query(rng.Uniform(-6, 6), rng.Uniform(-6, 6), rng.Uniform(-4, 8));
    int expected = -1;
    double expected_distance = inf;
    for (size_t i = 0; i < points.size(); ++i) {
      const double d = (points[i] - query).norm();
      if (d < expected_distance) {
        expected_distance = d;
        expected = static_cast<int>(i);
      }
    }
    double distance;
    EXPECT_EQ(grid.Nearest(query, inf, &distance), expected);
    EXPECT_DOUBLE_EQ(distance, expected_distance);
    // With a radius below the nearest distance nothing is found.
    EXPECT_EQ(grid.Nearest(query, 0.99 * expected_distance), -1);
  }
  EXPECT_EQ(PointGrid({}).Nearest(Eigen::Vector3d::Zero(), inf), -1);
}

}  // namespace
}  // namespace sylva
