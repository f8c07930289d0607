#include "reconstruct/attractors/livewire.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "datasets/eval/graph_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"

namespace sylva {
namespace {

constexpr int kSize = 200;
constexpr double kHalfWidth = 3.5;  // of the Y's strokes, pixels
const Eigen::Vector2d kFoot(100, 190), kFork(100, 100), kLeftTip(50, 30), kRightTip(150, 30);

// The Y as an attractor graph: foot (root) <- fork <- two tips.
AttractorGraph2D TrueY() {
  AttractorGraph2D y;
  y.width = y.height = kSize;
  y.root = y.AddNode(kFoot, -1);
  const int fork = y.AddNode(kFork, y.root);
  y.AddNode(kLeftTip, fork);
  y.AddNode(kRightTip, fork);
  return y;
}

// A dark Y on a light background (RGB) and its matte: pixels whose centre
// lies within kHalfWidth of the Y's segments.
void DrawY(FloatImage* photo, FloatImage* matte) {
  *photo = FloatImage(kSize, kSize, 3, 0.9f);
  *matte = FloatImage(kSize, kSize, 1, 0.0f);
  const auto segments = TrueY().Segments();
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      double d2 = 1e30;
      for (const auto& [a, b] : segments) d2 = std::min(d2, SegmentDistance2(p, a, b));
      if (d2 > kHalfWidth * kHalfWidth) continue;
      matte->at(x, y) = 1.0f;
      for (int c = 0; c < 3; ++c) photo->at(x, y, c) = 0.2f;
    }
  }
}

std::vector<int> Junctions(const AttractorGraph2D& graph) {
  std::vector<int> junctions;
  const auto children = graph.Children();
  for (int i = 0; i < graph.NumNodes(); ++i) {
    if (children[i].size() >= 2) junctions.push_back(i);
  }
  return junctions;
}

class LivewireYTest : public ::testing::Test {
 protected:
  void SetUp() override { DrawY(&photo_, &matte_); }
  FloatImage photo_, matte_;
};

TEST_F(LivewireYTest, SeedsAtTheTipsTraceTheY) {
  LivewireSummary summary;
  const AttractorGraph2D graph = TraceAttractorGraph(photo_, matte_, kFoot, {kLeftTip, kRightTip},
                                                     LivewireOptions(), &summary);
  graph.Check("traced Y");
  EXPECT_EQ(graph.source, "livewire");
  ASSERT_GE(graph.root, 0);
  EXPECT_EQ(graph.nodes[graph.root].position, kFoot);
  EXPECT_EQ(graph.Roots(), std::vector<int>{graph.root});
  EXPECT_LT(CompareGraphs2D(graph, TrueY(), 1.0).chamfer, 2.0);
  const std::vector<int> junctions = Junctions(graph);
  ASSERT_EQ(junctions.size(), 1u);
  EXPECT_LT((graph.nodes[junctions[0]].position - kFork).norm(), 8.0);
  EXPECT_EQ(summary.seeds, 2);
  EXPECT_EQ(summary.paths, 2);
  EXPECT_EQ(summary.nodes, graph.NumNodes());
}

TEST_F(LivewireYTest, AutomaticSeedsCoverTheY) {
  LivewireOptions options;
  options.num_seeds = 4;
  for (const std::string strategy : {"farthest_point", "skeleton_tips", "silhouette"}) {
    options.seeds = strategy;
    const AttractorGraph2D graph = TraceAttractorGraph(photo_, matte_, kFoot, {}, options);
    graph.Check(strategy);
    // Graph -> truth: the paths stay on the Y. Truth -> graph: both arms are
    // reached (not asked of four random outline points, which may all fall on
    // one arm).
    const PointSetDistances d = CompareGraphs2D(graph, TrueY(), 1.0);
    EXPECT_LT(d.mean_a_to_b, 4.0) << strategy;
    if (strategy != "silhouette") {
      EXPECT_LT(d.mean_b_to_a, 3.0) << strategy;
    }
  }
}

TEST_F(LivewireYTest, SnapMovesAnOffsetStrokeOntoTheTrunk) {
  AttractorGraph2D drawn;
  drawn.width = drawn.height = kSize;
  drawn.source = "strokes";
  drawn.root = drawn.AddNode({106, 185}, -1);
  drawn.AddNode({106, 110}, drawn.root);
  AttractorGraph2D trunk = drawn;
  trunk.nodes[0].position = {100, 185};
  trunk.nodes[1].position = {100, 110};
  ASSERT_NEAR(CompareGraphs2D(drawn, trunk, 1.0).chamfer, 6.0, 1e-9);
  const AttractorGraph2D snapped = SnapGraphToImage(drawn, photo_, matte_, LivewireOptions());
  snapped.Check("snapped");
  EXPECT_EQ(snapped.source, "strokes+livewire");
  EXPECT_EQ(snapped.Roots().size(), 1u);
  EXPECT_EQ(snapped.NumEdges(), snapped.NumNodes() - 1);
  EXPECT_LT(CompareGraphs2D(snapped, trunk, 1.0).chamfer, 1.5);
}

TEST_F(LivewireYTest, SameInputsGiveTheSameGraph) {
  LivewireOptions options;
  options.seeds = "silhouette";
  options.seed = 7;
  const AttractorGraph2D a = TraceAttractorGraph(photo_, matte_, kFoot, {}, options);
  const AttractorGraph2D b = TraceAttractorGraph(photo_, matte_, kFoot, {}, options);
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  for (int i = 0; i < a.NumNodes(); ++i) {
    EXPECT_EQ(a.nodes[i].position, b.nodes[i].position);
    EXPECT_EQ(a.nodes[i].parent_idx, b.nodes[i].parent_idx);
  }
  EXPECT_EQ(a.root, b.root);
}

TEST_F(LivewireYTest, FootPointIsTheMiddleOfTheLowestRun) {
  // The lowest row with pixel centres within 3.5 px of (100, 190) is row 192
  // (centre 192.5, 2.5 below): pixels 97..102.
  const Eigen::Vector2d foot = MatteFootPoint(matte_, 0.5);
  EXPECT_DOUBLE_EQ(foot.x(), 100.0);
  EXPECT_DOUBLE_EQ(foot.y(), 192.5);
  EXPECT_THROW(MatteFootPoint(FloatImage(10, 10, 1, 0.0f), 0.5), InputError);
}

// The message of the InputError `call` throws, or "" if it throws none.
template <typename Call>
std::string InputErrorOf(const Call& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(LivewireYTest, BadInputIsAnInputError) {
  const LivewireOptions options;
  const FloatImage small_matte(kSize / 2, kSize, 1, 1.0f);
  EXPECT_NE(InputErrorOf([&] {
              TraceAttractorGraph(photo_, small_matte, kFoot, {}, options);
            }).find("differs from the photo"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              TraceAttractorGraph(photo_, matte_, {-3, 10}, {}, options);
            }).find("livewire target"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              TraceAttractorGraph(photo_, matte_, kFoot, {{10, 250}}, options);
            }).find("livewire seed"),
            std::string::npos);
  const FloatImage empty(kSize, kSize, 1, 0.0f);
  EXPECT_NE(InputErrorOf([&] {
              TraceAttractorGraph(photo_, empty, kFoot, {}, options);
            }).find("nothing to trace"),
            std::string::npos);
  LivewireOptions bad = options;
  bad.seeds = "random";
  EXPECT_NE(InputErrorOf([&] { bad.Check(); }).find("Attractors.seeds"), std::string::npos);
  bad = options;
  bad.num_seeds = 0;
  EXPECT_NE(InputErrorOf([&] {
              TraceAttractorGraph(photo_, matte_, kFoot, {}, bad);
            }).find("Attractors.num_seeds"),
            std::string::npos);
  bad = options;
  bad.weight_outside = bad.weight_direction = bad.weight_centerline = 0;
  EXPECT_NE(InputErrorOf([&] { bad.Check(); }).find("Attractors.weight"), std::string::npos);
  bad = options;
  bad.matte_threshold = 1.0;
  EXPECT_NE(InputErrorOf([&] { bad.Check(); }).find("Attractors.matte_threshold"),
            std::string::npos);
  AttractorGraph2D drawn = TrueY();
  drawn.width = 50;
  EXPECT_NE(InputErrorOf([&] {
              SnapGraphToImage(drawn, photo_, matte_, options);
            }).find("drawn attractor graph"),
            std::string::npos);
}

// Automatic seeds on two views of a synthetic tree against the projection of
// its skeleton (orders <= 2). Thresholds: measured means + margin (see report).
TEST(LivewireSyntheticTest, AutomaticSeedsFollowTheTree) {
  SyntheticDatasetOptions data_options;
  data_options.num_views = 2;
  data_options.num_held_out = 0;
  data_options.image_size = 384;
  const SyntheticDataset data = MakeSyntheticDataset(data_options);
  for (int v = 0; v < data.image_set.NumViews(); ++v) {
    Eigen::Vector2d base;
    ASSERT_TRUE(data.image_set.Project(v, Eigen::Vector3d::Zero(), &base));
    const AttractorGraph2D graph =
        TraceAttractorGraph(data.photos[v], data.mattes[v], base, {}, LivewireOptions());
    graph.Check("synthetic view");
    const PointSetDistances d =
        CompareGraphs2D(graph, ProjectSkeleton(data.tree.skeleton, data.image_set, v, 2), 1.0);
    // Measured with the defaults: Chamfer 4.4 and 4.1 px (~1.1 % of the
    // image), graph -> truth 3.8 and 3.3 px.
    EXPECT_LT(d.chamfer, 6.5) << "view " << v;
    EXPECT_LT(d.mean_a_to_b, 5.5) << "view " << v;
  }
}

}  // namespace
}  // namespace sylva
