#include "sketch/branch_mrf.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A tree of known Omega: a trunk of 3 segments, and at every segment end
// one apical child (angle 15 +- 4 deg, ratio 0.85) and one lateral (angle
// 50 +- 6 deg, ratio 0.6) at a random azimuth, for `levels` generations.
SegmentTree TrueTree(uint64_t seed, int levels) {
  RandomEngine rng(seed);
  SegmentTree tree;
  int last = tree.AddPoint(Eigen::Vector3d::Zero(), -1);
  for (int k = 1; k <= 2; ++k) last = tree.AddPoint(Eigen::Vector3d(0, 0, 1.5 * k), last);
  std::vector<int> open = {last};
  for (int level = 0; level < levels; ++level) {
    std::vector<int> next;
    for (int tip : open) {
      const Eigen::Vector3d v = tree.points[tip] - tree.points[tree.parent[tip]];
      const Eigen::Vector3d axis = v.normalized();
      const Eigen::Vector3d side = axis.cross(Eigen::Vector3d::UnitX()).norm() > 0.1
                                       ? axis.cross(Eigen::Vector3d::UnitX()).normalized()
                                       : axis.cross(Eigen::Vector3d::UnitY()).normalized();
      const double azimuth = rng.Uniform(0, 360) * kDeg;
      const Eigen::Vector3d bend = Eigen::AngleAxisd(azimuth, axis) * side;
      for (const auto& [angle, sd, ratio] : {std::tuple{15.0, 4.0, 0.85}, {50.0, 6.0, 0.6}}) {
        const double a = rng.Normal(angle, sd) * kDeg;
        const Eigen::Vector3d dir = std::cos(a) * axis + std::sin(a) * (angle < 30 ? -bend : bend);
        next.push_back(tree.AddPoint(tree.points[tip] + ratio * v.norm() * dir, tip));
      }
    }
    open = next;
  }
  return tree;
}

// The drawing of `tree` seen along +Y: depths set to 0.
SegmentTree Drawn(const SegmentTree& tree) {
  SegmentTree drawn = tree;
  for (Eigen::Vector3d& p : drawn.points) p.y() = 0.0;
  return drawn;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

// Median |angle error| over parent-child relations, in degrees.
double MedianAngleError(const SegmentTree& truth, const SegmentTree& result) {
  std::vector<double> errors;
  auto angle = [](const SegmentTree& t, int i) {
    const int p = t.parent[i], g = t.parent[p];
    const Eigen::Vector3d vc = t.points[i] - t.points[p], vp = t.points[p] - t.points[g];
    return std::atan2(vc.cross(vp).norm(), vc.dot(vp)) / kDeg;
  };
  for (int i = 0; i < truth.Size(); ++i) {
    const int p = truth.parent[i];
    if (p < 0 || truth.parent[p] < 0) continue;
    errors.push_back(std::abs(angle(truth, i) - angle(result, i)));
  }
  return Median(errors);
}

double DepthOverWidth(const SegmentTree& tree) {
  Eigen::Vector3d lo = tree.points[0], hi = lo;
  for (const Eigen::Vector3d& p : tree.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi.y() - lo.y()) / (hi.x() - lo.x());
}

TEST(BranchMrfTest, LearnsTheParametersOfAKnownTree) {
  const SegmentTree tree = TrueTree(3, 6);
  const TreeParameters omega = LearnTreeParameters(tree);
  EXPECT_NEAR(omega.apical.angle_mean / kDeg, 15.0, 2.0);
  EXPECT_NEAR(omega.lateral.angle_mean / kDeg, 50.0, 2.0);
  EXPECT_NEAR(omega.apical.scale_mean, 0.85, 0.02);
  EXPECT_NEAR(omega.lateral.scale_mean, 0.6, 0.02);
  EXPECT_NEAR(omega.lateral.angle_sd / kDeg, 6.0, 1.5);
  EXPECT_GT(omega.apical.count, 50);
}

TEST(BranchMrfTest, SkeletonChainsBecomeSegmentsBetweenForks) {
  SkeletonGraph skeleton;
  int last = skeleton.AddNode({0, 0, 0}, 0.1, -1, 0);
  for (int k = 1; k <= 10; ++k) last = skeleton.AddNode({0, 0, 0.1 * k}, 0.1, last, 0);
  const int fork = last;
  for (int k = 1; k <= 5; ++k) last = skeleton.AddNode({0.1 * k, 0, 1.0}, 0.1, last, 1);
  last = fork;
  for (int k = 1; k <= 5; ++k) last = skeleton.AddNode({0, 0, 1.0 + 0.1 * k}, 0.1, last, 0);
  const SegmentTree tree = SegmentTreeOfSkeleton(skeleton, 0.01);
  ASSERT_EQ(tree.Size(), 4);  // root, fork, two tips
  EXPECT_NEAR((tree.points[1] - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
}

// The drawing of a tree of known Omega, inferred with that Omega as the
// template's: every depth is a free variable, yet the angles come back.
TEST(BranchMrfTest, DepthsOfADrawingGiveBackTheTreesAngles) {
  for (uint64_t seed : {1, 2, 3}) {
    const SegmentTree truth = TrueTree(seed, 4);
    MrfOptions options;
    options.seed = seed;
    const MrfResult result = InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(),
                                               LearnTreeParameters(truth), options);
    ASSERT_EQ(result.tree.Size(), truth.Size());
    // Only depths move: the result projects onto the drawing exactly.
    for (int i = 0; i < truth.Size(); ++i) {
      EXPECT_NEAR(result.tree.points[i].x(), truth.points[i].x(), 1e-12);
      EXPECT_NEAR(result.tree.points[i].z(), truth.points[i].z(), 1e-12);
    }
    const double error = MedianAngleError(truth, result.tree);
    const double flat = MedianAngleError(truth, Drawn(truth));
    std::printf(
        "seed %d: median angle error %.1f deg (flat drawing %.1f); depth/width %.2f "
        "(truth %.2f); %d sweeps, %d EM rounds\n",
        static_cast<int>(seed), error, flat, DepthOverWidth(result.tree), DepthOverWidth(truth),
        result.icm_sweeps, result.em_iterations);
    EXPECT_LT(error, 10.0) << seed;
    EXPECT_LT(error, 0.6 * flat) << seed;
    EXPECT_NEAR(DepthOverWidth(result.tree) / DepthOverWidth(truth), 1.0, 0.5) << seed;

    // Omega from another tree of the same kind (the exemplar a template
    // would be), not from this one.
    const MrfResult other =
        InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(),
                          LearnTreeParameters(TrueTree(seed + 100, 4)), options);
    const double other_error = MedianAngleError(truth, other.tree);
    std::printf("  Omega of another tree: %.1f deg; depth/width %.2f\n", other_error,
                DepthOverWidth(other.tree));
    EXPECT_LT(other_error, 0.6 * flat) << seed;
  }
}

TEST(BranchMrfTest, SameSeedSameTree) {
  const SegmentTree truth = TrueTree(5, 3);
  MrfOptions options;
  const TreeParameters omega = LearnTreeParameters(truth);
  MrfResult a = InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(), omega, options);
  MrfResult b = InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(), omega, options);
  PropagateBranches(truth, nullptr, options, &a);
  PropagateBranches(truth, nullptr, options, &b);
  ASSERT_EQ(a.tree.Size(), b.tree.Size());
  for (int i = 0; i < a.tree.Size(); ++i) EXPECT_EQ(a.tree.points[i], b.tree.points[i]);
}

TEST(BranchMrfTest, PropagationStaysInTheCrownAndWithinItsBudget) {
  const SegmentTree truth = TrueTree(7, 2);
  MrfOptions options;
  MrfResult result = InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(),
                                       LearnTreeParameters(truth), options);
  const int drawn = result.tree.Size();
  CrownOfRevolution crown;
  crown.bottom = 1.0;
  crown.step = 0.1;
  for (int k = 0; k < 60; ++k) crown.spans.push_back({-2.0, 2.0});
  PropagateBranches(
      truth, [&](const Eigen::Vector3d& p) { return crown.Contains(p); }, options, &result);
  EXPECT_GT(result.tree.Size(), 4 * drawn);
  for (int i = drawn; i < result.tree.Size(); ++i) {
    const Eigen::Vector3d& p = result.tree.points[i];
    EXPECT_LE(std::hypot(p.x(), p.y()), 2.0 + 1e-4) << i;
    EXPECT_LE(p.z(), 7.0 + 1e-4) << i;
  }
  options.max_segments = drawn + 10;
  MrfResult capped = InferBranchDepths(Drawn(truth), Eigen::Vector3d::UnitY(),
                                       LearnTreeParameters(truth), options);
  PropagateBranches(truth, nullptr, options, &capped);
  EXPECT_EQ(capped.tree.Size(), drawn + 10);
}

TEST(BranchMrfTest, TheTemplateIsTheExemplarWhoseFootprintIsNearest) {
  // A narrow exemplar (small angles) and a spreading one.
  auto exemplar = [](const std::string& name, double lateral_deg) {
    SkeletonGraph skeleton;
    const int root = skeleton.AddNode({0, 0, 0}, 0.1, -1, 0);
    int trunk = skeleton.AddNode({0, 0, 2}, 0.1, root, 0);
    for (int k = 0; k < 6; ++k) {
      const double az = k * 137.5 * kDeg, a = lateral_deg * kDeg;
      const Eigen::Vector3d dir(std::sin(a) * std::cos(az), std::sin(a) * std::sin(az),
                                std::cos(a));
      skeleton.AddNode(skeleton.nodes[trunk].position + 2.0 * dir, 0.05, trunk, 1);
      trunk = skeleton.AddNode(skeleton.nodes[trunk].position + Eigen::Vector3d(0, 0, 1), 0.1,
                               trunk, 0);
    }
    return MakeExemplar(name, skeleton);
  };
  const std::vector<TreeExemplar> exemplars = {exemplar("narrow", 20), exemplar("wide", 75)};
  const TreeExemplar wide = exemplar("probe", 70);
  EXPECT_EQ(SelectTemplate(exemplars, wide.footprints[0]), 1);
  const TreeExemplar narrow = exemplar("probe", 25);
  EXPECT_EQ(SelectTemplate(exemplars, narrow.footprints[0]), 0);
}

TEST(BranchMrfTest, SegmentsBecomeASkeleton) {
  const SegmentTree truth = TrueTree(2, 2);
  const SkeletonGraph skeleton = SkeletonOfSegments(truth, 0.25);
  skeleton.Check();
  EXPECT_GT(skeleton.NumNodes(), truth.Size());
  double length = 0;
  for (int i = 1; i < truth.Size(); ++i) {
    length += (truth.points[i] - truth.points[truth.parent[i]]).norm();
  }
  EXPECT_NEAR(skeleton.TotalLength(), length, 1e-9);
}

TEST(BranchMrfTest, BadOptionsAreNamed) {
  MrfOptions options;
  options.depth_candidates = 1;
  try {
    options.Check();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Sketch.mrf_candidates"), std::string::npos);
  }
}

}  // namespace
}  // namespace sylva
