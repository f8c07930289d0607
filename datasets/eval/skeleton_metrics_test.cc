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

}  // namespace
}  // namespace sylva
