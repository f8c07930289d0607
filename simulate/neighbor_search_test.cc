#include "simulate/neighbor_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Random points: a uniform cloud, a tight cluster, points on a line and exact
// duplicates (ties), so that every structure meets its awkward cases.
std::vector<Eigen::Vector3d> AwkwardPoints(uint64_t seed) {
  RandomEngine random(seed);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1500; ++i) {
    points.emplace_back(random.Uniform(-50, 50), random.Uniform(-20, 20), random.Uniform(0, 80));
  }
  for (int i = 0; i < 300; ++i) {
    points.emplace_back(random.Normal(3, 0.01), random.Normal(-4, 0.01), random.Normal(10, 0.01));
  }
  for (int i = 0; i < 100; ++i) points.emplace_back(10 + 0.5 * i, 0, 0);
  for (int i = 0; i < 50; ++i) points.push_back(points[7 * i]);
  return points;
}

class NeighborSearchTest : public ::testing::TestWithParam<NeighborSearchKind> {};

TEST_P(NeighborSearchTest, FindsTheTrueNearestNeighbour) {
  const std::vector<Eigen::Vector3d> points = AwkwardPoints(3);
  const auto reference = MakeNeighborSearch(NeighborSearchKind::kBruteForce);
  const auto search = MakeNeighborSearch(GetParam());
  reference->Build(points);
  search->Build(points);
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    for (double max_distance : {kInfinity, 2.0}) {
      double expected_distance = -1, distance = -1;
      const int expected = reference->NearestOther(i, max_distance, &expected_distance);
      ASSERT_EQ(search->NearestOther(i, max_distance, &distance), expected)
          << "point " << i << ", max distance " << max_distance;
      EXPECT_EQ(distance, expected_distance);
    }
  }
}

TEST_P(NeighborSearchTest, AnswersQueriesAwayFromThePoints) {
  const std::vector<Eigen::Vector3d> points = AwkwardPoints(4);
  const auto reference = MakeNeighborSearch(NeighborSearchKind::kBruteForce);
  const auto search = MakeNeighborSearch(GetParam());
  reference->Build(points);
  search->Build(points);
  RandomEngine random(5);
  for (int q = 0; q < 500; ++q) {
    // Inside and far outside the points' bounds.
    const Eigen::Vector3d query(random.Uniform(-200, 200), random.Uniform(-200, 200),
                                random.Uniform(-100, 200));
    double expected_distance = -1, distance = -1;
    const int expected = reference->Nearest(query, -1, kInfinity, &expected_distance);
    ASSERT_EQ(search->Nearest(query, -1, kInfinity, &distance), expected) << "query " << q;
    EXPECT_EQ(distance, expected_distance);
  }
}

TEST_P(NeighborSearchTest, BreaksTiesTowardsTheLowestIndex) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {1, 0, 0}};
  const auto search = MakeNeighborSearch(GetParam());
  search->Build(points);
  double distance = 0;
  EXPECT_EQ(search->NearestOther(0, kInfinity, &distance), 1);
  EXPECT_EQ(distance, 1.0);
  EXPECT_EQ(search->NearestOther(3, kInfinity, &distance), 1);
  EXPECT_EQ(distance, 0.0);
}

TEST_P(NeighborSearchTest, HandlesEmptyAndSingletonSetsAndRebuilds) {
  const auto search = MakeNeighborSearch(GetParam());
  std::vector<Eigen::Vector3d> points;
  search->Build(points);
  double distance = 0;
  EXPECT_EQ(search->Nearest(Eigen::Vector3d::Zero(), -1, kInfinity, &distance), -1);
  points = {{1, 2, 3}};
  search->Build(points);
  EXPECT_EQ(search->NearestOther(0, kInfinity, &distance), -1);
  EXPECT_EQ(search->Nearest(Eigen::Vector3d::Zero(), -1, kInfinity, &distance), 0);
  EXPECT_NEAR(distance, std::sqrt(14.0), 1e-12);
  // Beyond max_distance there is no neighbour.
  EXPECT_EQ(search->Nearest(Eigen::Vector3d::Zero(), -1, 3.0, &distance), -1);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, NeighborSearchTest,
                         ::testing::Values(NeighborSearchKind::kUniformGrid,
                                           NeighborSearchKind::kEmbree,
                                           NeighborSearchKind::kBruteForce),
                         [](const ::testing::TestParamInfo<NeighborSearchKind>& info) {
                           return std::string(NeighborSearchName(info.param));
                         });

TEST(NeighborSearchKindTest, ParsesNamesAndNamesTheOptionOnError) {
  EXPECT_EQ(NeighborSearchKindFromName("embree", "x"), NeighborSearchKind::kEmbree);
  EXPECT_EQ(NeighborSearchKindFromName("uniform_grid", "x"), NeighborSearchKind::kUniformGrid);
  try {
    NeighborSearchKindFromName("kd_tree", "ParticleFlow.neighbor_search");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "ParticleFlow.neighbor_search");
    EXPECT_NE(error.message().find("kd_tree"), std::string::npos);
  }
}

}  // namespace
}  // namespace sylva
