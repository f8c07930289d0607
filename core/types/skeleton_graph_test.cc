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

TEST(SkeletonGraphTest, CheckRejectsTwoRootsAndCycles) {
  SkeletonGraph two_roots;
  two_roots.AddNode({0, 0, 0}, 1, -1, 0);
  two_roots.AddNode({1, 0, 0}, 1, -1, 0);
  EXPECT_THROW(two_roots.Check(), Error);
  SkeletonGraph cycle;
  cycle.nodes = {{{0, 0, 0}, 1, -1, 0}, {{1, 0, 0}, 1, 2, 0}, {{2, 0, 0}, 1, 1, 0}};
  EXPECT_THROW(cycle.Check(), Error);
}

}  // namespace
}  // namespace sylva
