#include "sketch/stroke_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/io/attractor_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr double kPi = 3.14159265358979323846;

StrokeSet MakeSet(const std::vector<std::vector<Eigen::Vector2d>>& strokes) {
  StrokeSet set;
  set.width = 100;
  set.height = 100;
  for (const auto& points : strokes) set.strokes.push_back({points});
  return set;
}

// A "Y" drawn sloppily: the trunk up to the fork at (50, 55), the left arm
// starting 2 px off the fork, the right arm drawn from its tip down to 1.4 px
// short of the fork.
StrokeSet DrawnY() {
  return MakeSet({{{50, 95}, {50, 55}}, {{51, 57}, {20, 20}}, {{80, 20}, {49, 54}}});
}

int CountChildren(const AttractorGraph2D& graph, int node) {
  return static_cast<int>(graph.Children()[node].size());
}

// Every edge points down the picture (towards larger y), within `slack` px.
void ExpectEdgesPointDown(const AttractorGraph2D& graph, double slack) {
  for (const auto& [child, parent] : graph.Segments()) {
    EXPECT_GE(parent.y(), child.y() - slack) << child.transpose() << " -> " << parent.transpose();
  }
}

TEST(StrokeGraphTest, DrawnYBecomesOneTreeWithAForkAndEdgesDown) {
  StrokeGraphOptions options;
  const AttractorGraph2D graph = GraphFromStrokes(DrawnY(), options);
  graph.Check("test");
  EXPECT_EQ(graph.source, "strokes");
  EXPECT_EQ(graph.width, 100);
  ASSERT_EQ(graph.Roots(), std::vector<int>{0});
  EXPECT_EQ(graph.root, 0);
  EXPECT_EQ(graph.nodes[0].position, Eigen::Vector2d(50, 95));
  // Exactly one fork, at one of the three drawn ends near (50, 55) (the
  // trunk's end moved onto the right arm's, the nearest end); two tips at
  // the drawn ends.
  int forks = 0, tips = 0;
  Eigen::Vector2d fork(0, 0);
  for (int n = 0; n < graph.NumNodes(); ++n) {
    const int children = CountChildren(graph, n);
    if (children == 2) {
      ++forks;
      fork = graph.nodes[n].position;
      EXPECT_EQ(fork, Eigen::Vector2d(49, 54));
    }
    if (children == 0) {
      ++tips;
      const Eigen::Vector2d& p = graph.nodes[n].position;
      EXPECT_TRUE(p == Eigen::Vector2d(20, 20) || p == Eigen::Vector2d(80, 20)) << p.transpose();
    }
    EXPECT_LE(children, 2);
  }
  EXPECT_EQ(forks, 1);
  EXPECT_EQ(tips, 2);
  ExpectEdgesPointDown(graph, 0);
  // Straight lines from the base through the fork to the tips.
  const double expected = (Eigen::Vector2d(50, 95) - fork).norm() +
                          (Eigen::Vector2d(20, 20) - fork).norm() +
                          (Eigen::Vector2d(80, 20) - fork).norm();
  EXPECT_NEAR(graph.TotalLength(), expected, 1e-9);
  for (const auto& [a, b] : graph.Segments())
    EXPECT_LE((a - b).norm(), options.resample_spacing + 1e-9);
}

TEST(StrokeGraphTest, EndOnTheMiddleOfAStrokeSplitsIt) {
  // A branch ending 3 px beside the trunk's middle, no node there.
  const StrokeSet set = MakeSet({{{50, 95}, {50, 15}}, {{20, 30}, {47, 60}}});
  StrokeGraphOptions options;
  options.resample_spacing = std::numeric_limits<double>::infinity();
  const AttractorGraph2D graph = GraphFromStrokes(set, options);
  ASSERT_EQ(graph.NumNodes(), 4);  // the trunk's ends, the junction, the branch's far end
  EXPECT_EQ(graph.Roots().size(), 1u);
  int junction = -1;
  for (int n = 0; n < graph.NumNodes(); ++n) {
    if (CountChildren(graph, n) == 2) junction = n;
  }
  ASSERT_GE(junction, 0);
  EXPECT_TRUE(graph.nodes[junction].position.isApprox(Eigen::Vector2d(50, 60)));
  EXPECT_EQ(graph.nodes[graph.nodes[junction].parent_idx].position, Eigen::Vector2d(50, 95));
}

TEST(StrokeGraphTest, DisjointStrokesGiveTwoComponentsMainRootOnTheLonger) {
  const StrokeSet set = MakeSet({{{10, 10}, {10, 40}}, {{60, 20}, {60, 90}}});
  const AttractorGraph2D graph = GraphFromStrokes(set, StrokeGraphOptions());
  graph.Check("test");
  const std::vector<int> roots = graph.Roots();
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_EQ(graph.nodes[graph.root].position, Eigen::Vector2d(60, 90));  // the longer one's bottom
  EXPECT_EQ(graph.nodes[roots[1]].position, Eigen::Vector2d(10, 40));
  ExpectEdgesPointDown(graph, 0);
  EXPECT_NEAR(graph.TotalLength(), 100, 1e-9);
}

TEST(StrokeGraphTest, GivenRootInTheMiddleSplitsAndOrientsBothWays) {
  StrokeSet set = MakeSet({{{50, 95}, {50, 15}}});
  set.root = Eigen::Vector2d(53, 60);  // 3 px beside the stroke
  StrokeGraphOptions options;
  options.resample_spacing = std::numeric_limits<double>::infinity();
  const AttractorGraph2D graph = GraphFromStrokes(set, options);
  ASSERT_EQ(graph.NumNodes(), 3);
  EXPECT_TRUE(graph.nodes[graph.root].position.isApprox(Eigen::Vector2d(50, 60)));
  EXPECT_EQ(CountChildren(graph, graph.root), 2);  // the part below points up to the root
  // The root lies in the smaller component: that one becomes the main one.
  set.strokes.push_back({{{0, 0}, {0, 99}}});
  const AttractorGraph2D two = GraphFromStrokes(set, options);
  EXPECT_TRUE(two.nodes[two.root].position.isApprox(Eigen::Vector2d(50, 60)));
  EXPECT_EQ(two.Roots().size(), 2u);
}

TEST(StrokeGraphTest, CrossingStrokesWithoutNearEndsStayApart) {
  const StrokeSet set = MakeSet({{{10, 10}, {90, 90}}, {{10, 90}, {90, 10}}});
  EXPECT_EQ(GraphFromStrokes(set, StrokeGraphOptions()).Roots().size(), 2u);
}

TEST(StrokeGraphTest, CycleIsCutWithoutLosingAnySegment) {
  // A triangle of three strokes meeting end to end, plus a trunk below.
  const StrokeSet set = MakeSet(
      {{{50, 95}, {50, 60}}, {{50, 60}, {20, 20}}, {{20, 20}, {80, 20}}, {{80, 20}, {50, 60}}});
  const AttractorGraph2D graph = GraphFromStrokes(set, StrokeGraphOptions());
  graph.Check("test");
  EXPECT_EQ(graph.Roots().size(), 1u);
  EXPECT_NEAR(graph.TotalLength(), 35 + 50 + 60 + 50, 1e-9);
  // Exactly one node is a copy: its position is shared with another node.
  int shared = 0;
  for (int a = 0; a < graph.NumNodes(); ++a) {
    for (int b = a + 1; b < graph.NumNodes(); ++b) {
      shared += graph.nodes[a].position == graph.nodes[b].position;
    }
  }
  EXPECT_EQ(shared, 1);
  // By symmetry the cut is at the top edge's middle (80 px along both ways).
  for (int a = 0; a < graph.NumNodes(); ++a) {
    for (int b = a + 1; b < graph.NumNodes(); ++b) {
      if (graph.nodes[a].position == graph.nodes[b].position) {
        EXPECT_NEAR(graph.nodes[a].position.y(), 20, 1e-9);
        EXPECT_NEAR(graph.nodes[a].position.x(), 50, 4 + 1e-9);  // within half a spacing
      }
    }
  }
}

TEST(StrokeGraphTest, DenseCurveIsSimplifiedWithinTolerance) {
  std::vector<Eigen::Vector2d> arc;
  for (int k = 0; k <= 1000; ++k) {
    const double angle = kPi * k / 1000;
    arc.push_back(Eigen::Vector2d(50 + 40 * std::cos(angle), 90 - 40 * std::sin(angle)));
  }
  StrokeGraphOptions options;
  options.resample_spacing = std::numeric_limits<double>::infinity();
  const AttractorGraph2D graph = GraphFromStrokes(MakeSet({arc}), options);
  EXPECT_LT(graph.NumNodes(), 60);
  EXPECT_GT(graph.NumNodes(), 10);
  for (const AttractorNode& node : graph.nodes)
    EXPECT_NEAR((node.position - Eigen::Vector2d(50, 90)).norm(), 40, 1e-9);
  EXPECT_NEAR(graph.TotalLength(), 40 * kPi, 40 * kPi * 5e-3);  // chords are a bit shorter
}

TEST(StrokeGraphTest, DeterministicAndOptionsChecked) {
  const AttractorGraph2D a = GraphFromStrokes(DrawnY(), StrokeGraphOptions());
  const AttractorGraph2D b = GraphFromStrokes(DrawnY(), StrokeGraphOptions());
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  for (int n = 0; n < a.NumNodes(); ++n) {
    EXPECT_EQ(a.nodes[n].position, b.nodes[n].position);
    EXPECT_EQ(a.nodes[n].parent_idx, b.nodes[n].parent_idx);
  }
  StrokeGraphOptions bad;
  bad.snap_distance = -1;
  try {
    GraphFromStrokes(DrawnY(), bad);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Attractors.stroke_snap_distance");
  }
  bad = StrokeGraphOptions();
  bad.resample_spacing = 0;
  EXPECT_THROW(GraphFromStrokes(DrawnY(), bad), InputError);
  EXPECT_THROW(GraphFromStrokes(MakeSet({}), StrokeGraphOptions()), InputError);
}

TEST(StrokeGraphTest, SvgFileToAttractorFile) {
  // A person's drawing on a 1440 x 1080 photo in a half-size document.
  const fs::path dir = fs::temp_directory_path() / "sylva_stroke_graph_test";
  fs::create_directories(dir);
  AtomicWriteString(dir / "IMG_0001.jpg.strokes.svg", R"(<svg viewBox="0 0 720 540">
    <g id="layer1">
      <path d="M 360 530 C 362 450 350 350 359 280"/>
      <path d="m 361 282 q 30 -40 75 -80"/>
      <path d="M 250 120 L 300 200 L 357 279"/>
      <circle id="root" cx="360" cy="532" r="4"/>
    </g></svg>)");
  const StrokeSet strokes = ReadStrokes(dir / "IMG_0001.jpg.strokes.svg", 1440, 1080);
  const AttractorGraph2D graph = GraphFromStrokes(strokes, StrokeGraphOptions());
  EXPECT_EQ(graph.Roots().size(), 1u);
  EXPECT_TRUE(graph.nodes[graph.root].position.isApprox(Eigen::Vector2d(720, 1060)));
  ExpectEdgesPointDown(graph, 0.5);
  WriteAttractorGraphJson(dir / "IMG_0001.jpg.json", graph, "IMG_0001.jpg");
  const AttractorGraph2D back = ReadAttractorGraphJson(dir / "IMG_0001.jpg.json");
  EXPECT_EQ(back.NumNodes(), graph.NumNodes());
  EXPECT_EQ(back.source, "strokes");
  EXPECT_DOUBLE_EQ(back.TotalLength(), graph.TotalLength());
}

}  // namespace
}  // namespace sylva
