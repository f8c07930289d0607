#include "simulate/trace_graph.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/util/check.h"

namespace sylva {
namespace {

// Two particles flow down along x = -2..0 and x = 2..0 and merge above the
// root in straight lines.
TEST(TraceGraphTest, RecordsMergesAndSimplifiesChains) {
  TraceGraph graph(Eigen::Vector3d(0, 0, 0));
  TraceCursor left = graph.StartTrace(Eigen::Vector3d(-2, 0, 10), 0);
  TraceCursor right = graph.StartTrace(Eigen::Vector3d(2, 0, 10), 1);
  Eigen::Vector3d left_at(-2, 0, 10), right_at(2, 0, 10);
  for (int step = 1; step <= 4; ++step) {
    const Eigen::Vector3d left_next(-2 + 0.5 * step, 0, 10 - step);
    const Eigen::Vector3d right_next(2 - 0.5 * step, 0, 10 - step);
    if (TraceGraph::LeavesRun(left, left_at, left_next, 1e-9)) graph.RecordNode(&left, left_at, 1);
    if (TraceGraph::LeavesRun(right, right_at, right_next, 1e-9))
      graph.RecordNode(&right, right_at, 1);
    TraceGraph::StartRunIfNeeded(&left, left_next);
    TraceGraph::StartRunIfNeeded(&right, right_next);
    left_at = left_next;
    right_at = right_next;
  }
  // Both are at (0, 0, 6): the left one survives and absorbs the right one.
  const int junction = graph.NodeAtPosition(&left, left_at, 1);
  graph.NodeAtPosition(&right, right_at, 1);
  graph.EndTrace(right, junction, 1);
  EXPECT_EQ(graph.strands(junction), 2);
  graph.EndTrace(left, TraceGraph::kRoot, 2);

  const SkeletonGraph raw = graph.ToSkeleton(SimFrame(), Eigen::Vector3d(0, 0, 0), 0.0);
  EXPECT_NO_THROW(raw.Check());
  EXPECT_EQ(raw.RootIdx(), 0);
  EXPECT_EQ(raw.nodes[0].strands, 2);
  EXPECT_EQ(raw.Tips().size(), 2u);
  // Straight runs record only their ends: root, junction, the absorbed
  // particle's last position (here at the junction) and two tips.
  EXPECT_EQ(raw.NumNodes(), 5);
  // Simplification drops the absorbed particle's last node.
  EXPECT_EQ(graph.ToSkeleton(SimFrame(), Eigen::Vector3d::Zero(), 0.1).NumNodes(), 4);

  // With a frame, positions are in world units.
  SimFrame frame{Eigen::Vector3d(1, 1, 1), 0.5};
  const SkeletonGraph world = graph.ToSkeleton(frame, Eigen::Vector3d(7, 7, 7), 0.0);
  EXPECT_EQ(world.nodes[0].position, Eigen::Vector3d(7, 7, 7));
  EXPECT_TRUE(world.nodes[1].position.isApprox(Eigen::Vector3d(1, 1, 4)));
}

TEST(TraceGraphTest, DouglasPeuckerKeepsCornersAndDropsNearlyStraightNodes) {
  TraceGraph graph(Eigen::Vector3d(0, 0, 0));
  TraceCursor cursor = graph.StartTrace(Eigen::Vector3d(0, 0, 10), 0);
  // Down with a small wiggle, then a sharp corner to the root.
  graph.RecordNode(&cursor, Eigen::Vector3d(0.05, 0, 8), 1);
  graph.RecordNode(&cursor, Eigen::Vector3d(-0.05, 0, 6), 1);
  graph.RecordNode(&cursor, Eigen::Vector3d(0, 0, 4), 1);
  graph.RecordNode(&cursor, Eigen::Vector3d(3, 0, 2), 1);
  graph.EndTrace(cursor, TraceGraph::kRoot, 1);
  EXPECT_EQ(graph.ToSkeleton(SimFrame(), Eigen::Vector3d::Zero(), 0.0).NumNodes(), 6);
  const SkeletonGraph simple = graph.ToSkeleton(SimFrame(), Eigen::Vector3d::Zero(), 0.2);
  EXPECT_NO_THROW(simple.Check());
  // Root, the corner at (3, 0, 2), (0, 0, 4) and the tip remain.
  EXPECT_EQ(simple.NumNodes(), 4);
  for (const SkeletonNode& node : simple.nodes) EXPECT_EQ(node.strands, 1);
}

TEST(TraceGraphTest, RunsBreakWhenThePathBendsOrTurnsBack) {
  TraceCursor cursor;
  cursor.anchor = Eigen::Vector3d::Zero();
  TraceGraph::StartRunIfNeeded(&cursor, Eigen::Vector3d(0, 0, -1));
  const Eigen::Vector3d from(0, 0, -2);
  EXPECT_FALSE(TraceGraph::LeavesRun(cursor, from, Eigen::Vector3d(0.05, 0, -3), 0.1));
  EXPECT_TRUE(TraceGraph::LeavesRun(cursor, from, Eigen::Vector3d(0.2, 0, -3), 0.1));
  EXPECT_TRUE(TraceGraph::LeavesRun(cursor, from, Eigen::Vector3d(0, 0, -1.5), 0.1));
}

// Nodes know their trace; edges are listed once, in the order they were
// made, a split adding only its upper part.
TEST(TraceGraphTest, ListsTracesAndEdgesInOrder) {
  TraceGraph graph(Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(graph.TraceOf(TraceGraph::kRoot), TraceGraph::kRootTrace);
  TraceCursor a = graph.StartTrace(Eigen::Vector3d(0, 0, 10), 3);
  TraceCursor b = graph.StartTrace(Eigen::Vector3d(1, 0, 10), 7);
  const int a_tip = a.last_node, b_tip = b.last_node;
  const int a_middle = graph.RecordNode(&a, Eigen::Vector3d(0, 0, 5), 1);
  graph.EndTrace(a, TraceGraph::kRoot, 1);
  graph.EndTrace(b, a_middle, 1);
  EXPECT_EQ(graph.TraceOf(a_tip), 3);
  EXPECT_EQ(graph.TraceOf(a_middle), 3);
  EXPECT_EQ(graph.TraceOf(b_tip), 7);
  EXPECT_EQ(graph.EdgesInOrder(), (std::vector<int32_t>{a_tip, a_middle, b_tip}));
  const int split = graph.SplitEdge(a_middle, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(graph.TraceOf(split), 3);
  EXPECT_EQ(graph.EdgesInOrder(), (std::vector<int32_t>{a_tip, a_middle, b_tip, split}));
  EXPECT_EQ(graph.strands(split), 2);
  EXPECT_THROW(graph.StartTrace(Eigen::Vector3d::Zero(), -1), Error);
}

}  // namespace
}  // namespace sylva
