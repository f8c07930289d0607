#include "simulate/trace_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace sylva {
namespace {

// A finished trace: tip (0, 0, 10) -> (0, 0, 5) -> root (0, 0, 0), plus a
// long straight one from (20, 0, 10) to the root.
struct Scene {
  TraceGraph graph{Eigen::Vector3d::Zero()};
  int tip = -1, middle = -1, long_tip = -1;
  Scene() {
    TraceCursor cursor = graph.StartTrace(Eigen::Vector3d(0, 0, 10), 0);
    tip = cursor.last_node;
    middle = graph.RecordNode(&cursor, Eigen::Vector3d(0, 0, 5), 1);
    graph.EndTrace(cursor, TraceGraph::kRoot, 1);
    TraceCursor other = graph.StartTrace(Eigen::Vector3d(20, 0, 10), 1);
    long_tip = other.last_node;
    graph.EndTrace(other, TraceGraph::kRoot, 1);
  }
};

TEST(TraceIndexTest, FindsTheNearestEdgeWithinTheJoinDistance) {
  Scene scene;
  TraceIndex index(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(30), 1.0);
  index.AddSubtree(scene.graph, scene.middle);
  index.AddEdge(scene.graph, scene.long_tip);
  int child = -1;
  Eigen::Vector3d point;
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(0.5, 0, 7), &child, &point));
  EXPECT_EQ(child, scene.tip);
  EXPECT_TRUE(point.isApprox(Eigen::Vector3d(0, 0, 7)));
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(0, 0.9, 2), &child, &point));
  EXPECT_EQ(child, scene.middle);
  // Halfway along the long edge (covered by samples, not by its bounds).
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(10, 0.5, 5), &child, &point));
  EXPECT_EQ(child, scene.long_tip);
  EXPECT_FALSE(index.Nearest(scene.graph, Eigen::Vector3d(1.5, 0, 7), &child, &point));
  EXPECT_FALSE(index.Nearest(scene.graph, Eigen::Vector3d(100, 0, 7), &child, &point));
}

TEST(TraceIndexTest, NothingJoinsAtAFreeTip) {
  Scene scene;
  TraceIndex index(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(30), 1.0);
  index.AddSubtree(scene.graph, scene.middle);
  int child = -1;
  Eigen::Vector3d point;
  // Beyond the tip, the nearest point of its edge is the tip itself.
  EXPECT_FALSE(index.Nearest(scene.graph, Eigen::Vector3d(0, 0, 10.5), &child, &point));
}

TEST(TraceIndexTest, SplitEdgesStayCovered) {
  Scene scene;
  TraceIndex index(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(30), 1.0);
  index.AddEdge(scene.graph, scene.long_tip);
  const int split = scene.graph.SplitEdge(scene.long_tip, Eigen::Vector3d(10, 0, 5));
  index.AddEdge(scene.graph, split);
  EXPECT_EQ(scene.graph.Parent(scene.long_tip), split);
  EXPECT_EQ(scene.graph.Parent(split), TraceGraph::kRoot);
  int child = -1;
  Eigen::Vector3d point;
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(15, 0.5, 7.5), &child, &point));
  EXPECT_EQ(child, scene.long_tip);
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(5, 0.5, 2.5), &child, &point));
  EXPECT_EQ(child, split);
}

// Edges are indexed as the traces grow; a predicate skips some (a particle's
// own trace).
TEST(TraceIndexTest, IndexesNewEdgesAndSkipsRejectedOnes) {
  Scene scene;
  TraceIndex index(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(30), 1.0);
  index.AddNewEdges(scene.graph);
  int child = -1;
  Eigen::Vector3d point;
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(0.5, 0, 7), &child, &point));
  EXPECT_EQ(child, scene.tip);
  // Without the nearest edge, the next one within reach; none beyond.
  const auto not_tip = [&](int edge) { return edge != scene.tip; };
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(0.5, 0, 5.5), not_tip, &child, &point));
  EXPECT_EQ(child, scene.middle);
  EXPECT_FALSE(index.Nearest(scene.graph, Eigen::Vector3d(0.5, 0, 7), not_tip, &child, &point));
  // A trace started later is found once its edges are added.
  TraceCursor late = scene.graph.StartTrace(Eigen::Vector3d(10, 10, 10), 5);
  scene.graph.RecordNode(&late, Eigen::Vector3d(10, 10, 0), 1);
  EXPECT_FALSE(index.Nearest(scene.graph, Eigen::Vector3d(10.5, 10, 5), &child, &point));
  index.AddNewEdges(scene.graph);
  ASSERT_TRUE(index.Nearest(scene.graph, Eigen::Vector3d(10.5, 10, 5), &child, &point));
  EXPECT_EQ(scene.graph.TraceOf(child), 5);
}

// The index against every edge tested in child order, with the index's rule
// (strictly within the join distance, ties to the lowest child, not at a
// free tip), on traces of short and long edges in every direction.
TEST(TraceIndexTest, AgreesWithTestingEveryEdge) {
  const double join = 1.0;
  TraceGraph graph{Eigen::Vector3d(20, 20, 0)};
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto random_step = [&](double longest) {
    Eigen::Vector3d step(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5);
    return step.normalized() * (0.1 + longest * unit(random));
  };
  for (int trace = 0; trace < 60; ++trace) {
    Eigen::Vector3d p(40 * unit(random), 40 * unit(random), 5 + 30 * unit(random));
    TraceCursor cursor = graph.StartTrace(p, trace);
    for (int node = 0; node < 6; ++node) {
      p = (p + random_step(node % 2 == 0 ? 1.5 : 12.0)).cwiseMax(0.0).cwiseMin(40.0);
      graph.RecordNode(&cursor, p, 1);
    }
    graph.EndTrace(cursor, TraceGraph::kRoot, 1);
  }
  TraceIndex index(Eigen::Vector3d::Constant(-2), Eigen::Vector3d::Constant(42), join);
  index.AddNewEdges(graph);
  const std::vector<int32_t>& edges = graph.EdgesInOrder();
  std::vector<int32_t> children(edges.begin(), edges.end());
  std::sort(children.begin(), children.end());
  int found = 0;
  for (int q = 0; q < 4000; ++q) {
    // Half the queries near a random edge, half anywhere.
    Eigen::Vector3d point(40 * unit(random), 40 * unit(random), 40 * unit(random));
    if (q % 2 == 0) {
      const int edge = children[random() % children.size()];
      const Eigen::Vector3d a = graph.Position(edge), b = graph.Position(graph.Parent(edge));
      point = a + unit(random) * (b - a) + random_step(1.5 * join);
    }
    int expected = -1;
    double best2 = join * join;
    for (const int child : children) {
      double t;
      const double d2 =
          SegmentDistance2(point, graph.Position(child), graph.Position(graph.Parent(child)), &t);
      if (!(d2 < best2) || (t == 0.0 && graph.IsTip(child))) continue;
      best2 = d2;
      expected = child;
    }
    int child = -1;
    Eigen::Vector3d on_edge;
    const bool near = index.Nearest(graph, point, &child, &on_edge);
    ASSERT_EQ(near, expected >= 0) << "query " << q << " at " << point.transpose();
    if (near) {
      EXPECT_EQ(child, expected) << "query " << q;
      ++found;
    }
  }
  EXPECT_GT(found, 1000);  // most queries near an edge find one
}

}  // namespace
}  // namespace sylva
