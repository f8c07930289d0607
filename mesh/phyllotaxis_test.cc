#include "mesh/phyllotaxis.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;

std::vector<Eigen::Vector3d> StraightAxis(const Eigen::Vector3d& direction, double length) {
  return {Eigen::Vector3d::Zero(), 0.5 * length * direction.normalized(),
          length * direction.normalized()};
}

// A quarter circle of radius 1 from vertical to horizontal, 200 segments.
std::vector<Eigen::Vector3d> BentAxis() {
  std::vector<Eigen::Vector3d> axis;
  for (int i = 0; i <= 200; ++i) {
    const double a = 0.5 * M_PI * i / 200;
    axis.emplace_back(1.0 - std::cos(a), 0.3 * a, std::sin(a));
  }
  return axis;
}

// Divergence between leaf i and leaf i + step, averaged over the axis.
double MeanDivergence(const std::vector<LeafAttachment>& leaves, int step) {
  double sum = 0.0;
  int count = 0;
  for (size_t i = 0; i + step < leaves.size(); i += step) {
    sum += DivergenceAngleDeg(leaves[i], leaves[i + step]);
    ++count;
  }
  return sum / count;
}

TEST(PhyllotaxisTest, SpiralDivergenceIsTheGoldenAngleOnStraightAndBentAxes) {
  PhyllotaxisOptions options;
  options.internode = 0.02;
  for (const auto& axis :
       {StraightAxis({0, 0, 1}, 1.0), StraightAxis({1, 1, 0}, 1.0), BentAxis()}) {
    const std::vector<LeafAttachment> leaves = PlaceLeavesAlongAxis(axis, options);
    ASSERT_GT(leaves.size(), 40u);
    EXPECT_NEAR(MeanDivergence(leaves, 1), 137.5, 1.0);
    for (size_t i = 0; i + 1 < leaves.size(); ++i) {
      EXPECT_NEAR(DivergenceAngleDeg(leaves[i], leaves[i + 1]), 137.5, 1.5) << i;
    }
  }
  options.divergence_deg = 120.0;  // tristichous
  EXPECT_NEAR(MeanDivergence(PlaceLeavesAlongAxis(BentAxis(), options), 1), 120.0, 1.0);
}

TEST(PhyllotaxisTest, AlternateDecussateAndWhorledAngles) {
  PhyllotaxisOptions options;
  options.internode = 0.05;
  options.pattern = PhyllotaxisPattern::kAlternate;
  std::vector<LeafAttachment> leaves = PlaceLeavesAlongAxis(BentAxis(), options);
  EXPECT_NEAR(MeanDivergence(leaves, 1), 180.0, 1.0);

  options.pattern = PhyllotaxisPattern::kOppositeDecussate;
  leaves = PlaceLeavesAlongAxis(BentAxis(), options);
  ASSERT_EQ(leaves.size() % 2, 0u);
  EXPECT_NEAR(MeanDivergence(leaves, 2), 90.0, 1.0);  // successive pairs
  for (size_t i = 0; i + 1 < leaves.size(); i += 2) {
    EXPECT_EQ(leaves[i].node, leaves[i + 1].node);
    EXPECT_NEAR(DivergenceAngleDeg(leaves[i], leaves[i + 1]), 180.0, 1e-6);  // within a pair
  }

  options.pattern = PhyllotaxisPattern::kWhorled;
  options.leaves_per_whorl = 4;
  leaves = PlaceLeavesAlongAxis(StraightAxis({0, 1, 1}, 1.0), options);
  ASSERT_EQ(leaves.size() % 4, 0u);
  EXPECT_NEAR(MeanDivergence(leaves, 4), 45.0, 1e-6);  // whorls offset by 180 / n
  EXPECT_NEAR(DivergenceAngleDeg(leaves[0], leaves[1]), 90.0, 1e-6);
  EXPECT_STREQ(PhyllotaxisPatternName(options.pattern), "whorled");
}

TEST(PhyllotaxisTest, NodesSpacingPetiolesAndNormals) {
  PhyllotaxisOptions options;
  options.internode = 0.1;
  options.first_node = 0.5;
  options.insertion_deg = 50.0;
  const std::vector<LeafAttachment> leaves =
      PlaceLeavesAlongAxis(StraightAxis({0, 0, 1}, 1.0), options);
  ASSERT_EQ(leaves.size(), 10u);  // nodes at 0.05, 0.15, ..., 0.95
  for (size_t i = 0; i < leaves.size(); ++i) {
    EXPECT_NEAR(leaves[i].position.z(), 0.05 + 0.1 * i, 1e-12);
    EXPECT_NEAR(leaves[i].position.head<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(std::acos(leaves[i].petiole_direction.z()) / kDegree, 50.0, 1e-9);
    EXPECT_NEAR(leaves[i].normal.dot(leaves[i].petiole_direction), 0.0, 1e-12);
    EXPECT_GT(leaves[i].normal.z(), 0.0);  // the upper face looks up the shoot
    EXPECT_NEAR(leaves[i].normal.norm(), 1.0, 1e-12);
  }
  // First azimuth 90 degrees from "up": on a horizontal shoot, distichous
  // leaves spread sideways (horizontal petioles when inserted at 90).
  options.pattern = PhyllotaxisPattern::kAlternate;
  options.insertion_deg = 90.0;
  for (const LeafAttachment& leaf : PlaceLeavesAlongAxis(StraightAxis({1, 0, 0}, 1.0), options)) {
    EXPECT_NEAR(leaf.petiole_direction.z(), 0.0, 1e-12);
    EXPECT_NEAR(std::abs(leaf.petiole_direction.y()), 1.0, 1e-12);
  }
}

TEST(PhyllotaxisTest, RadialDirectionFollowsTheAzimuthConvention) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  EXPECT_LT((RadialDirection(x, 0.0) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((RadialDirection(x, 90.0) + Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((RadialDirection(Eigen::Vector3d(0, 0, 2), 0.0) - x).norm(), 1e-12);
  // The first leaf of an axis sits at the same azimuth.
  PhyllotaxisOptions options;
  options.insertion_deg = 90.0;
  options.first_azimuth_deg = 30.0;
  const LeafAttachment first = PlaceLeavesAlongAxis(StraightAxis(x, 1.0), options)[0];
  EXPECT_LT((first.petiole_direction - RadialDirection(x, 30.0)).norm(), 1e-12);
}

TEST(PhyllotaxisTest, ShortAxesAndBadOptions) {
  PhyllotaxisOptions options;
  options.internode = 1.0;
  EXPECT_TRUE(PlaceLeavesAlongAxis(StraightAxis({0, 0, 1}, 0.4), options).empty());
  EXPECT_TRUE(
      PlaceLeavesAlongAxis({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, options).empty());
  options.internode = 0.0;
  try {
    PlaceLeavesAlongAxis(StraightAxis({0, 0, 1}, 1.0), options);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Phyllotaxis.internode");
  }
  EXPECT_THROW(ParsePhyllotaxisPattern("fibonacci", "Leaves.phyllotaxis"), InputError);
  EXPECT_EQ(ParsePhyllotaxisPattern("decussate", "x"), PhyllotaxisPattern::kOppositeDecussate);
}

}  // namespace
}  // namespace sylva
