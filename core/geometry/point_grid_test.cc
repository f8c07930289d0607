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

TEST(PointGridTest, FlatAndLinearSetsGetUsefulCells) {
  // Points in a plane and on a line: no volume, but cells must stay near
  // the points' spacing (a collapsed cell size made queries crawl).
  std::vector<Eigen::Vector3d> plane, line;
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j) plane.emplace_back(0.01 * i, 0.0, 0.01 * j);
    line.emplace_back(0.0, 0.0, 0.01 * i);
  }
  const PointGrid plane_grid(plane), line_grid(line);
  EXPECT_NEAR(plane_grid.cell_size(), 0.015, 0.005);
  EXPECT_NEAR(line_grid.cell_size(), 0.015, 0.005);
  EXPECT_EQ(plane_grid.Nearest({0.504, 3.0, 0.296}, 10.0), 50 * 100 + 30);
  EXPECT_EQ(line_grid.Nearest({0.5, 0.5, 0.0}, 10.0), 0);
  EXPECT_EQ(PointGrid({Eigen::Vector3d::Ones()}).cell_size(), 1.0);
}

TEST(PointGridTest, TooFineCellsAreEnlargedAndStayExact) {
  // 1 mm cells over a 100 m spread would need 10^15 cells.
  RandomEngine rng(9);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 2000; ++i) {
    points.emplace_back(rng.Uniform(0, 100), rng.Uniform(0, 100), rng.Uniform(0, 100));
  }
  points.push_back(points[7]);  // a duplicate: the lower index wins
  const PointGrid grid(points, 1e-3);
  EXPECT_GT(grid.cell_size(), 0.5);
  EXPECT_EQ(grid.Nearest(points[7], 1.0), 7);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d query(rng.Uniform(-20, 120), rng.Uniform(-20, 120), rng.Uniform(0, 100));
    int expected = -1;
    double expected_distance = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < points.size(); ++i) {
      const double d = (points[i] - query).norm();
      if (d < expected_distance) {
        expected_distance = d;
        expected = static_cast<int>(i);
      }
    }
    EXPECT_EQ(grid.Nearest(query, 1e9), expected);
    EXPECT_EQ(grid.Nearest(query, 1.01 * expected_distance), expected);
  }
}

}  // namespace
}  // namespace sylva
