#include "datasets/eval/skeleton_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva {
namespace {

// A 10 m vertical trunk with one 4 m horizontal branch at 5 m.
SkeletonGraph TrueTree() {
  SkeletonGraph tree;
  const int root = tree.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int fork = tree.AddNode({0, 0, 5}, 0.15, root, 0);
  tree.AddNode({0, 0, 10}, 0.1, fork, 0);
  tree.AddNode({4, 0, 5}, 0.05, fork, 1);
  return tree;
}

TEST(CompareSkeletonsTest, IdenticalSkeletonsMatchExactly) {
  const SkeletonComparison c = CompareSkeletons(TrueTree(), TrueTree(), 10.0);
  EXPECT_NEAR(c.length_ratio, 1.0, 1e-12);
  EXPECT_NEAR(c.precision, 1.0, 1e-12);
  EXPECT_NEAR(c.recall, 1.0, 1e-12);
  EXPECT_NEAR(c.chamfer, 0.0, 1e-12);
  ASSERT_EQ(c.orders.size(), 2u);
  EXPECT_EQ(c.orders[0].axes, 1);
  EXPECT_NEAR(c.orders[0].length, 10.0, 1e-12);
  EXPECT_EQ(c.orders[1].axes, 1);
  EXPECT_NEAR(c.orders[1].length, 4.0, 1e-12);
}

TEST(CompareSkeletonsTest, ExtraWoodLowersPrecisionAndMissedWoodRecall) {
  // The trunk 0.1 m off (within 2 % of 10 m), a 6 m stick where the truth
  // has nothing, and no horizontal branch.
  SkeletonGraph ours;
  const int root = ours.AddNode({0.1, 0, 0}, 0, -1, 0);
  const int fork = ours.AddNode({0.1, 0, 2}, 0, root, 0);
  ours.AddNode({0.1, 0, 10}, 0, fork, 0);
  ours.AddNode({0.1, 6, 2}, 0, fork, 1);
  const SkeletonComparison c = CompareSkeletons(ours, TrueTree(), 10.0);
  EXPECT_NEAR(c.length_ratio, 16.0 / 14.0, 1e-12);
  // The stick's first 0.2 m (minus a sliver) lie within 0.2 m of the trunk.
  EXPECT_NEAR(c.precision, (10.0 + std::sqrt(0.2 * 0.2 - 0.1 * 0.1)) / 16.0, 0.003);
  // Of the branch only its first 0.3 m lie within 0.2 m of our trunk.
  EXPECT_NEAR(c.recall, 10.3 / 14.0, 0.003);
  EXPECT_GT(c.chamfer, 0.1);
  EXPECT_EQ(c.orders[1].axes, 1);
  EXPECT_EQ(c.true_orders[1].axes, 1);
}

// A 10 m trunk (5 strands) and a branch (1 strand) that leaves it at 2 m,
// goes out 2 m, up 5 m, back to 5 cm beside the trunk and up it 2.5 m.
SkeletonGraph TreeWithABranchBesideTheTrunk(int branch_strands) {
  SkeletonGraph tree;
  const int root = tree.AddNode({0, 0, 0}, 0, -1, 0);
  tree.nodes[root].strands = 5 + branch_strands;
  const int fork = tree.AddNode({0, 0, 2}, 0, root, 0);
  tree.nodes[fork].strands = 5 + branch_strands;
  tree.nodes[tree.AddNode({0, 0, 10}, 0, fork, 0)].strands = 5;
  int k = fork;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(2, 0, 2), Eigen::Vector3d(2, 0, 7),
                                   Eigen::Vector3d(0.05, 0, 7), Eigen::Vector3d(0.05, 0, 9.5)}) {
    k = tree.AddNode(p, 0, k, 1);
    tree.nodes[k].strands = branch_strands;
  }
  return tree;
}

TEST(DuplicatedLengthTest, TheThinnerOfTwoTracesBesideEachOtherCounts) {
  // Within 0.1 m of the trunk: the last 2.5 m and the last 5 cm before them.
  EXPECT_NEAR(DuplicatedLength(TreeWithABranchBesideTheTrunk(1), 0.1, 0.01), 2.55, 0.02);
  // A thicker branch: the trunk's 2.5 m beside it count instead, and the
  // 2 x 8.7 cm of trunk within 0.1 m of the branch's turn at 7 m.
  EXPECT_NEAR(DuplicatedLength(TreeWithABranchBesideTheTrunk(9), 0.1, 0.01),
              2.5 + 2 * std::sqrt(0.1 * 0.1 - 0.05 * 0.05), 0.03);
}

TEST(DuplicatedLengthTest, ForksAndSeparateBranchesAreNotDuplicates) {
  EXPECT_EQ(DuplicatedLength(TrueTree(), 0.2, 0.02), 0.0);
  // Two branches leaving one fork 60 degrees apart are never within the
  // radius where they are 3 radii apart along the skeleton; 30 degrees
  // apart, they are for about a radius.
  for (const double half_angle : {0.53, 0.26}) {
    SkeletonGraph fork;
    const int root = fork.AddNode({0, 0, 0}, 0, -1, 0);
    fork.AddNode({std::sin(half_angle), 0, std::cos(half_angle)}, 0, root, 0);
    fork.AddNode({-std::sin(half_angle), 0, std::cos(half_angle)}, 0, root, 1);
    const double duplicated = DuplicatedLength(fork, 0.1, 0.01);
    if (half_angle > 0.5) {
      EXPECT_EQ(duplicated, 0.0);
    } else {
      EXPECT_GT(duplicated, 0.03);
      EXPECT_LT(duplicated, 0.1);
    }
  }
  // The figure in a comparison: none in the truth, the branch's in ours.
  const SkeletonComparison c = CompareSkeletons(TreeWithABranchBesideTheTrunk(1), TrueTree(), 10.0);
  EXPECT_NEAR(c.duplicated_length, 2.55, 0.02);
  EXPECT_EQ(c.true_duplicated_length, 0.0);
  EXPECT_NEAR(c.length_ratio_once, (c.length - c.duplicated_length) / 14.0, 1e-12);
}

}  // namespace
}  // namespace sylva
