#include "core/types/attractor_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// A "Y": root at the bottom, a trunk of 10 collinear nodes, two arms.
AttractorGraph2D MakeY() {
  AttractorGraph2D graph;
  graph.width = 100;
  graph.height = 100;
  graph.root = graph.AddNode({50, 95}, -1);
  int parent = graph.root;
  for (int k = 1; k <= 10; ++k) parent = graph.AddNode({50, 95 - 4.0 * k}, parent);
  const int fork = parent;  // (50, 55)
  graph.AddNode({30, 30}, graph.AddNode({36, 45}, fork));
  graph.AddNode({70, 30}, fork);
  return graph;
}

TEST(AttractorGraph, RootsChildrenLengthAndSamples) {
  const AttractorGraph2D graph = MakeY();
  graph.Check("test");
  EXPECT_EQ(graph.Roots(), std::vector<int>{0});
  EXPECT_EQ(graph.NumEdges(), graph.NumNodes() - 1);
  EXPECT_EQ(graph.Children()[10].size(), 2u);
  const double arm1 = std::hypot(14.0, 10.0) + std::hypot(6.0, 15.0);
  const double arm2 = std::hypot(20.0, 25.0);
  EXPECT_NEAR(graph.TotalLength(), 40 + arm1 + arm2, 1e-9);
  for (const Eigen::Vector2d& p : graph.SamplePoints(1.0)) {
    double best = 1e9;
    for (const auto& [a, b] : graph.Segments()) {
      const Eigen::Vector2d ab = b - a;
      const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * ab - p).norm());
    }
    EXPECT_LT(best, 1e-9);
  }
  EXPECT_GE(graph.SamplePoints(1.0).size(), static_cast<size_t>(graph.TotalLength()));
}

TEST(AttractorGraph, SimplifiedKeepsRootsJunctionsTipsAndShape) {
  const AttractorGraph2D simple = MakeY().Simplified(0.5);
  simple.Check("simplified");
  // Root, fork, the bend of the first arm, two tips.
  ASSERT_EQ(simple.NumNodes(), 5);
  EXPECT_EQ(simple.nodes[simple.root].position, Eigen::Vector2d(50, 95));
  EXPECT_NEAR(simple.TotalLength(), MakeY().TotalLength(), 1e-9);
  EXPECT_EQ(MakeY().Simplified(0.0).NumNodes(), MakeY().NumNodes());
}

TEST(AttractorGraph, WithoutTwigsDropsShortSideChainsOnly) {
  AttractorGraph2D graph = MakeY();  // arms of 31.1 and 32.0 px from the fork
  // A 3 px spur on the trunk, and a 5 px twig (2 nodes) on the second arm's tip.
  graph.AddNode({53, 75}, 5);
  const int arm_tip = 13;  // (70, 30)
  graph.AddNode({73, 26}, graph.AddNode({71, 28}, arm_tip));
  graph.Check("spurs");
  const AttractorGraph2D pruned = graph.WithoutTwigs(10.0);
  pruned.Check("pruned");
  // The spur goes; the lengthened arm (no junction on it) stays whole.
  EXPECT_EQ(pruned.NumNodes(), MakeY().NumNodes() + 2);
  EXPECT_NEAR(pruned.TotalLength(),
              MakeY().TotalLength() + std::hypot(1.0, 2.0) + std::hypot(2.0, 2.0), 1e-9);
  // Above the arms' lengths, the first arm goes; the fork is then no
  // junction, and the second arm continues the trunk down to the root.
  const AttractorGraph2D trunk_only = MakeY().WithoutTwigs(100.0);
  ASSERT_EQ(trunk_only.NumNodes(), 12);
  EXPECT_EQ(trunk_only.nodes[trunk_only.root].position, Eigen::Vector2d(50, 95));
  EXPECT_EQ(trunk_only.nodes.back().position, Eigen::Vector2d(70, 30));
  EXPECT_EQ(MakeY().WithoutTwigs(0.0).NumNodes(), MakeY().NumNodes());
}

TEST(AttractorGraph, ScaledAndCheckErrors) {
  const AttractorGraph2D half = MakeY().Scaled(0.5);
  EXPECT_EQ(half.width, 50);
  EXPECT_EQ(half.nodes[0].position, Eigen::Vector2d(25, 47.5));

  AttractorGraph2D cycle = MakeY();
  cycle.nodes[0].parent_idx = 3;  // root -> 3 -> 2 -> 1 -> root
  EXPECT_THROW(cycle.Check("cycle"), InputError);
  AttractorGraph2D bad_parent = MakeY();
  bad_parent.nodes[2].parent_idx = 99;
  EXPECT_THROW(bad_parent.Check("bad"), InputError);
  AttractorGraph2D bad_root = MakeY();
  bad_root.root = 4;
  EXPECT_THROW(bad_root.Check("root"), InputError);
  AttractorGraph2D nan = MakeY();
  nan.nodes[5].position.x() = std::nan("");
  EXPECT_THROW(nan.Check("nan"), InputError);
  AttractorGraph2D no_size = MakeY();
  no_size.width = 0;
  EXPECT_THROW(no_size.Check("size"), InputError);
}

TEST(AttractorGraph, FitsAspectOfResizedCopiesNotCrops) {
  AttractorGraph2D graph = MakeY();  // 100 x 100
  EXPECT_TRUE(graph.FitsAspectOf(100, 100));
  EXPECT_TRUE(graph.FitsAspectOf(400, 400));
  EXPECT_TRUE(graph.FitsAspectOf(400, 403));   // 0.75 % off: a rounded resize
  EXPECT_FALSE(graph.FitsAspectOf(400, 405));  // 1.25 % off
  EXPECT_FALSE(graph.FitsAspectOf(400, 300));  // a crop
  graph.width = 1333;  // a 4000 x 3000 photo drawn on at a third of its size
  graph.height = 1000;
  EXPECT_TRUE(graph.FitsAspectOf(4000, 3000));
  EXPECT_FALSE(graph.FitsAspectOf(3000, 4000));  // rotated
  graph.width = 0;
  EXPECT_FALSE(graph.FitsAspectOf(100, 100));
}

}  // namespace
}  // namespace sylva
