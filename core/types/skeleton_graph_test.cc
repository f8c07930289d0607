#include "core/types/skeleton_graph.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(SkeletonGraphTest, BuildsAndChecksATree) {
  SkeletonGraph graph;
  const int root = graph.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int top = graph.AddNode({0, 0, 2}, 0.1, root, 0);
  graph.AddNode({1, 0, 2}, 0.05, top, 1);
  EXPECT_EQ(graph.RootIdx(), root);
  EXPECT_NO_THROW(graph.Check());
  EXPECT_DOUBLE_EQ(graph.TotalLength(), 3.0);
  EXPECT_EQ(graph.Children()[top].size(), 1u);
  // Nodes plus interior samples every 0.5 along 3 units of edges.
  EXPECT_EQ(graph.SamplePoints(0.5).size(), 3u + 3u + 1u);
}

TEST(SkeletonGraphTest, HeightIsTheHighestNodeAboveTheRoot) {
  EXPECT_EQ(SkeletonGraph().Height(), 0.0);
  SkeletonGraph graph;
  // Root at z = 1.5, not the lowest node: a root hanging below it (z = 0.5)
  // and the top at z = 4 give a height of 2.5.
  const int root = graph.AddNode({3, -2, 1.5}, 0.2, -1, 0);
  graph.AddNode({3, -2, 0.5}, 0.1, root, 1);
  const int top = graph.AddNode({2, -2, 4}, 0.1, root, 0);
  graph.AddNode({0, -2, 3}, 0.1, top, 1);
  EXPECT_DOUBLE_EQ(graph.Height(), 2.5);
  // A single node, or every node below the root: height 0.
  SkeletonGraph hanging;
  hanging.AddNode({0, 0, 1}, 0.1, -1, 0);
  EXPECT_EQ(hanging.Height(), 0.0);
  hanging.AddNode({0, 0, -1}, 0.1, 0, 0);
  EXPECT_EQ(hanging.Height(), 0.0);
}

TEST(SkeletonGraphTest, BranchAxesFollowTheMostStrands) {
  // 0 -> 1 -> {2 (3 strands) -> 4, 3 (5 strands) -> 5 -> {6, 7 (1 strand)}}
  SkeletonGraph graph;
  graph.AddNode({0, 0, 0}, 1, -1, 0);
  graph.AddNode({0, 0, 1}, 1, 0, 0);
  graph.AddNode({1, 0, 2}, 1, 1, 0);
  graph.AddNode({-1, 0, 2}, 1, 1, 0);
  graph.AddNode({2, 0, 3}, 1, 2, 0);
  graph.AddNode({-1, 0, 3}, 1, 3, 0);
  graph.AddNode({-1, 0, 4}, 1, 5, 0);
  graph.AddNode({-2, 0, 4}, 1, 5, 0);
  const int strands[] = {8, 8, 3, 5, 3, 5, 4, 1};
  for (int i = 0; i < 8; ++i) graph.nodes[i].strands = strands[i];
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = graph.BranchAxes(&orders);
  ASSERT_EQ(axes.size(), 3u);
  EXPECT_EQ(axes[0], (BranchAxis{0, 1, 3, 5, 6}));
  EXPECT_EQ(axes[1], (BranchAxis{1, 2, 4}));
  EXPECT_EQ(axes[2], (BranchAxis{5, 7}));
  EXPECT_EQ(orders, (std::vector<int>{0, 1, 1}));
  graph.AssignOrders();
  EXPECT_EQ(graph.nodes[1].order, 0);
  EXPECT_EQ(graph.nodes[4].order, 1);
  EXPECT_EQ(graph.nodes[7].order, 1);
  EXPECT_EQ(graph.Tips(), (std::vector<int>{4, 6, 7}));
}

TEST(SkeletonGraphTest, CheckRejectsTwoRootsAndCycles) {
  SkeletonGraph two_roots;
  two_roots.AddNode({0, 0, 0}, 1, -1, 0);
  two_roots.AddNode({1, 0, 0}, 1, -1, 0);
  EXPECT_THROW(two_roots.Check(), Error);
  SkeletonGraph cycle;
  cycle.nodes = {{{0, 0, 0}, 1, -1, 0, 0}, {{1, 0, 0}, 1, 2, 0, 0}, {{2, 0, 0}, 1, 1, 0, 0}};
  EXPECT_THROW(cycle.Check(), Error);
}

TEST(SkeletonPathLengthsTest, DistancesRunAlongTheEdges) {
  // Children listed before their parents: a trunk 0 -> 2 (z 0 -> 4) with a
  // 3 m branch at 2 m (node 1) and a 1 m twig at its end (node 0).
  SkeletonGraph tree;
  tree.nodes.resize(5);
  tree.nodes[3] = {{0, 0, 0}, 0, -1, 0};
  tree.nodes[4] = {{0, 0, 2}, 0, 3, 0};
  tree.nodes[2] = {{0, 0, 4}, 0, 4, 0};
  tree.nodes[1] = {{3, 0, 2}, 0, 4, 1};
  tree.nodes[0] = {{3, 0, 3}, 0, 1, 2};
  const SkeletonPathLengths paths(tree);
  EXPECT_DOUBLE_EQ(paths.FromRoot(0, {3, 0, 2.5}), 5.5);
  EXPECT_DOUBLE_EQ(paths.FromRoot(2, {0, 0, 3}), 3.0);
  // From the twig's middle to the trunk at 3 m: down to the fork and up.
  EXPECT_DOUBLE_EQ(paths.Between(0, 5.5, 2, 3.0), 3.5 + 1.0);
  // The same edge, and a point below the other on its way to the root.
  EXPECT_DOUBLE_EQ(paths.Between(1, 3.0, 1, 4.0), 1.0);
  EXPECT_DOUBLE_EQ(paths.Between(4, 1.0, 0, 5.5), 4.5);
}

}  // namespace
}  // namespace sylva
