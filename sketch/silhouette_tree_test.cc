#include "sketch/silhouette_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/util/check.h"

namespace sylva {
namespace {

// A crown of `lobes` round bumps on a circle of radius 3 m centred 6 m up,
// and a trunk from the ground to 7 m.
Outline2 LobedCrown(int lobes) {
  Outline2 crown;
  for (int k = 0; k < 360; ++k) {
    const double a = k * M_PI / 180;
    const double r = 3.0 + 0.6 * std::abs(std::cos(0.5 * lobes * a));
    crown.emplace_back(r * std::cos(a), 6.0 + r * std::sin(a));
  }
  return crown;
}

const Outline2 kTrunk = {{0, 0}, {0, 7.0}};

double Length(const Outline2& line) {
  double length = 0;
  for (size_t i = 1; i < line.size(); ++i) length += (line[i] - line[i - 1]).norm();
  return length;
}

// Section 3: one major branch into each bump above the crown's underside,
// ending inside the crown, leaving the trunk at the BAF's angle.
TEST(SilhouetteTreeTest, MajorBranchesEndInTheBumps) {
  SilhouetteTreeOptions options;
  options.levels = 1;
  options.max_overlap = 0.0;  // no coverage branches: only the bumps'
  const Outline2 crown = LobedCrown(8);
  const SilhouetteStructure s = InferSilhouetteStructure(kTrunk, crown, {}, {}, options);
  int majors = 0;
  for (const SilhouetteBranch& b : s.branches) {
    if (b.level != 1) continue;
    ++majors;
    EXPECT_TRUE(InsideOutline(crown, b.points.back()));
    EXPECT_NEAR(b.points.front().x(), 0.0, 1e-9) << "grows from the trunk";
    EXPECT_GT(b.points.front().y(), 3.0) << "inside the crown";
    // The angle to the trunk at the base: the BAF between 70 and 30 degrees
    // (measured on the curve's first chord, a 32nd of it, which bends a few
    // degrees towards the end).
    const Eigen::Vector2d leave = (b.points[1] - b.points[0]).normalized();
    const double angle = std::acos(leave.y()) * 180 / M_PI;
    const double baf = 70.0 + (30.0 - 70.0) * b.u;
    EXPECT_NEAR(angle, baf, 8.0) << "u " << b.u;
    // Its sub-silhouette: closed, around its end.
    EXPECT_GE(b.crown.size(), 8u);
    EXPECT_TRUE(InsideOutline(b.crown, 0.5 * (b.points.back() + b.points[b.points.size() / 2])));
  }
  // 8 lobes, those above the trunk's entry into the crown (y = 3): 6 or 7.
  EXPECT_GE(majors, 5);
  EXPECT_LE(majors, 8);
}

// A drawn branch replaces the inferred one nearest it and keeps its shape;
// the inferred siblings take its shape in their span frames.
TEST(SilhouetteTreeTest, DrawnBranchesReplaceAndRestyleTheInferred) {
  SilhouetteTreeOptions options;
  options.levels = 1;
  options.max_overlap = 0.0;
  const Outline2 crown = LobedCrown(6);
  // An S-shaped branch to the right bump.
  Outline2 drawn;
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 20.0;
    drawn.emplace_back(3.2 * t, 4.5 + 1.5 * t + 0.4 * std::sin(2 * M_PI * t));
  }
  const SilhouetteStructure s = InferSilhouetteStructure(kTrunk, crown, {}, {drawn}, options);
  EXPECT_EQ(s.drawn_branches, 1);
  int drawn_found = 0;
  for (const SilhouetteBranch& b : s.branches) {
    if (b.level != 1) continue;
    if (b.drawn_shape) {
      ++drawn_found;
      EXPECT_TRUE(b.points.back().isApprox(drawn.back()));
      continue;
    }
    // The copy's shape: as long relative to its span as the drawn one.
    const double drawn_ratio = Length(drawn) / (drawn.back() - drawn.front()).norm();
    const double ratio = Length(b.points) / (b.points.back() - b.points.front()).norm();
    EXPECT_NEAR(ratio, drawn_ratio, 0.02);
  }
  EXPECT_EQ(drawn_found, 1);
}

// A sub-silhouette drawn around one major branch becomes its crown; its
// branching is copied to the siblings.
TEST(SilhouetteTreeTest, DrawnSubSilhouettesAreCopiedToSiblings) {
  SilhouetteTreeOptions options;
  options.levels = 2;
  const Outline2 crown = LobedCrown(6);
  const SilhouetteStructure plain = InferSilhouetteStructure(kTrunk, crown, {}, {}, options);
  // Find the right-hand major branch and draw a lobed crown around its end.
  int right = -1;
  for (size_t b = 1; b < plain.branches.size(); ++b) {
    if (plain.branches[b].level == 1 && !plain.branches[b].coverage &&
        (right < 0 ||
         plain.branches[b].points.back().x() > plain.branches[right].points.back().x())) {
      right = static_cast<int>(b);
    }
  }
  ASSERT_GE(right, 0);
  const Eigen::Vector2d centre = plain.branches[right].points.back();
  Outline2 sub;
  for (int k = 0; k < 120; ++k) {
    const double a = k * M_PI / 60;
    const double r = 0.9 + 0.25 * std::abs(std::cos(2.5 * a));
    sub.emplace_back(centre.x() + r * std::cos(a) - 0.4, centre.y() + r * std::sin(a));
  }
  const SilhouetteStructure s = InferSilhouetteStructure(kTrunk, crown, {sub}, {}, options);
  EXPECT_EQ(s.drawn_crowns, 1);
  EXPECT_GE(s.copied_styles, 1);
  // Every major branch without a drawn crown carries as many children as
  // the one with it (copied), unless it has its own drawn crown.
  int drawn_children = -1;
  std::vector<int> children(s.branches.size(), 0);
  for (const SilhouetteBranch& b : s.branches) {
    if (b.parent >= 0) ++children[b.parent];
  }
  for (size_t b = 0; b < s.branches.size(); ++b) {
    if (s.branches[b].drawn_crown) drawn_children = children[b];
  }
  ASSERT_GT(drawn_children, 0);
  for (size_t b = 0; b < s.branches.size(); ++b) {
    if (s.branches[b].level == 1 && !s.branches[b].drawn_crown) {
      EXPECT_EQ(children[b], drawn_children) << b;
    }
  }
}

// Section 5.4: with closeness alone, free branches spread evenly around
// the parent; the spiral pattern turns successive branches by ~144 degrees.
TEST(SilhouetteTreeTest, GibbsProcessSpreadsAndFollowsThePattern) {
  SilhouetteTreeOptions options;
  options.phyllotaxis = "none";
  std::vector<InsertionPoint> points;
  for (int k = 0; k < 4; ++k) points.push_back({0.5, 0.0, true, 0.0, 360.0});
  const double before = GibbsCost(points, options);
  const double after = PlaceByGibbs(options, 7, &points);
  EXPECT_LT(after, before);
  std::vector<double> thetas;
  for (const InsertionPoint& p : points) thetas.push_back(p.theta);
  std::sort(thetas.begin(), thetas.end());
  for (size_t k = 0; k < thetas.size(); ++k) {
    const double gap =
        k + 1 < thetas.size() ? thetas[k + 1] - thetas[k] : thetas[0] + 360 - thetas[k];
    EXPECT_NEAR(gap, 90.0, 20.0);
  }
  options.phyllotaxis = "spiral";
  points.clear();
  for (int k = 0; k < 8; ++k) points.push_back({(k + 0.5) / 8, 0.0, true, 0.0, 360.0});
  PlaceByGibbs(options, 7, &points);
  int near_pattern = 0;
  for (size_t k = 0; k + 1 < points.size(); ++k) {
    double turn = std::fmod(points[k + 1].theta - points[k].theta + 720.0, 360.0);
    const double off = std::min(std::abs(turn - 144.0), std::abs(turn - 216.0));
    near_pattern += off < 25.0;
  }
  EXPECT_GE(near_pattern, 5);
  // Drawn branches stay within their domain.
  points = {{0.3, 0.0, true, -45.0, 45.0}, {0.3, 180.0, true, 135.0, 225.0}};
  PlaceByGibbs(options, 3, &points);
  EXPECT_TRUE(points[0].theta <= 45.0 || points[0].theta >= 315.0) << points[0].theta;
  EXPECT_TRUE(points[1].theta >= 135.0 && points[1].theta <= 225.0) << points[1].theta;
}

// Section 5: the 3D tree keeps the trunk and every branch's length, is
// not flat, and is the same for the same seed.
TEST(SilhouetteTreeTest, PlacedTreeIsDeepAndDeterministic) {
  SilhouetteTreeOptions options;
  const SilhouetteStructure s = InferSilhouetteStructure(kTrunk, LobedCrown(7), {}, {}, options);
  const SilhouetteTree a = PlaceSilhouetteTree(s, 0.2, options);
  const SilhouetteTree b = PlaceSilhouetteTree(s, 0.2, options);
  EXPECT_NO_THROW(a.skeleton.Check());
  ASSERT_EQ(a.skeleton.NumNodes(), b.skeleton.NumNodes());
  for (int i = 0; i < a.skeleton.NumNodes(); ++i) {
    EXPECT_EQ(a.skeleton.nodes[i].position, b.skeleton.nodes[i].position);
  }
  double low_x = 1e9, high_x = -1e9, low_y = 1e9, high_y = -1e9;
  for (const SkeletonNode& n : a.skeleton.nodes) {
    low_x = std::min(low_x, n.position.x()), high_x = std::max(high_x, n.position.x());
    low_y = std::min(low_y, n.position.y()), high_y = std::max(high_y, n.position.y());
  }
  EXPECT_GT(high_y - low_y, 0.5 * (high_x - low_x)) << "depth against width";
  EXPECT_GT(a.extra_branches, 0);
  // The branches reach the crown's top (9.6 m), not beyond.
  EXPECT_NEAR(a.skeleton.Height(), 9.6, 0.6);
}

TEST(SilhouetteTreeTest, RejectsBadInput) {
  SilhouetteTreeOptions options;
  EXPECT_THROW(InferSilhouetteStructure({{0, 0}}, LobedCrown(5), {}, {}, options), InputError);
  EXPECT_THROW(InferSilhouetteStructure(kTrunk, {{0, 0}, {1, 1}}, {}, {}, options), InputError);
  options.phyllotaxis = "fibonacci";
  EXPECT_THROW(options.Check(), InputError);
  options = SilhouetteTreeOptions();
  options.levels = 0;
  EXPECT_THROW(options.Check(), InputError);
}

}  // namespace
}  // namespace sylva
