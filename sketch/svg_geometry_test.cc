#include "sketch/svg_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTolerance = 0.25;

using Polyline = std::vector<Eigen::Vector2d>;
using Curve = std::function<Eigen::Vector2d(double)>;  // t in [0, 1]

double DistanceToPolyline(const Eigen::Vector2d& p, const Polyline& line) {
  double best2 = (p - line.front()).squaredNorm();
  for (size_t k = 0; k + 1 < line.size(); ++k) {
    best2 = std::min(best2, SegmentDistance2(p, line[k], line[k + 1]));
  }
  return std::sqrt(best2);
}

// Both ways: the exact curve within `tolerance` of the polyline, and every
// polyline vertex on the curve (to within 1e-9 of a dense sampling's chords).
void ExpectFollowsCurve(const Polyline& line, const Curve& curve, double tolerance) {
  Polyline dense;
  for (int k = 0; k <= 20000; ++k) dense.push_back(curve(k / 20000.0));
  double worst = 0;
  for (const Eigen::Vector2d& p : dense) worst = std::max(worst, DistanceToPolyline(p, line));
  EXPECT_LE(worst, tolerance);
  EXPECT_GT(worst, tolerance / 20) << "suspiciously many points: " << line.size();
  for (const Eigen::Vector2d& v : line)
    EXPECT_LT(DistanceToPolyline(v, dense), 1e-3) << v.transpose();
  EXPECT_LT((line.front() - curve(0)).norm(), 1e-12);
  EXPECT_LT((line.back() - curve(1)).norm(), 1e-12);
}

Curve Cubic(Eigen::Vector2d p0, Eigen::Vector2d p1, Eigen::Vector2d p2, Eigen::Vector2d p3) {
  return [=](double t) -> Eigen::Vector2d {
    const double s = 1 - t;
    return s * s * s * p0 + 3 * s * s * t * p1 + 3 * s * t * t * p2 + t * t * t * p3;
  };
}
Curve Quad(Eigen::Vector2d p0, Eigen::Vector2d p1, Eigen::Vector2d p2) {
  return [=](double t) -> Eigen::Vector2d {
    return (1 - t) * (1 - t) * p0 + 2 * (1 - t) * t * p1 + t * t * p2;
  };
}
// Two curves one after the other, over [0, 0.5] and [0.5, 1].
Curve Join(Curve a, Curve b) {
  return [=](double t) { return t <= 0.5 ? a(2 * t) : b(2 * t - 1); };
}
Polyline Single(const std::vector<Polyline>& lines) {
  EXPECT_EQ(lines.size(), 1u);
  return lines.empty() ? Polyline() : lines[0];
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.message();
  }
  return "(no error)";
}

const Eigen::Affine2d kIdentity = Eigen::Affine2d::Identity();

TEST(SvgNumbersTest, ParsesPackedNumbersAndRejectsJunk) {
  EXPECT_EQ(ParseSvgNumbers("10,20 -3.5e1-.5 +3 1.5.5 7E+1"),
            (std::vector<double>{10, 20, -35, -0.5, 3, 1.5, 0.5, 70}));
  EXPECT_TRUE(ParseSvgNumbers("  ").empty());
  EXPECT_NE(ErrorOf([] { ParseSvgNumbers("1 x"); }).find("expected a number at character 3"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSvgNumbers("1e999"); }).find("out of range"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSvgNumbers("nan"); }).find("expected a number"), std::string::npos);
}

TEST(SvgNumbersTest, LengthsInUserUnits) {
  EXPECT_DOUBLE_EQ(ParseSvgLength("12"), 12);
  EXPECT_DOUBLE_EQ(ParseSvgLength("12px"), 12);
  EXPECT_DOUBLE_EQ(ParseSvgLength("2in"), 192);
  EXPECT_DOUBLE_EQ(ParseSvgLength("25.4mm"), 96);
  EXPECT_DOUBLE_EQ(ParseSvgLength("72pt"), 96);
  EXPECT_NE(ErrorOf([] { ParseSvgLength("50%"); }).find("unsupported length unit '%'"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSvgLength("2em"); }).find("unit 'em'"), std::string::npos);
}

TEST(SvgTransformTest, EveryFunctionAndComposition) {
  const auto apply = [](const char* text, Eigen::Vector2d p) {
    return ParseSvgTransform(text) * p;
  };
  EXPECT_TRUE(apply("", {3, 4}).isApprox(Eigen::Vector2d(3, 4)));
  // Right to left: scale first, then translate.
  EXPECT_TRUE(apply("translate(10 20) scale(2)", {1, 1}).isApprox(Eigen::Vector2d(12, 22)));
  EXPECT_TRUE(apply("scale(2),translate(10,20)", {1, 1}).isApprox(Eigen::Vector2d(22, 42)));
  EXPECT_TRUE(apply("translate(5)", {1, 1}).isApprox(Eigen::Vector2d(6, 1)));
  EXPECT_TRUE(apply("scale(2 3)", {1, 1}).isApprox(Eigen::Vector2d(2, 3)));
  EXPECT_TRUE(apply("rotate(90)", {1, 0}).isApprox(Eigen::Vector2d(0, 1)));
  EXPECT_TRUE(apply("rotate(90 10 10)", {20, 10}).isApprox(Eigen::Vector2d(10, 20)));
  EXPECT_TRUE(apply("matrix(1 2 3 4 5 6)", {1, 1}).isApprox(Eigen::Vector2d(9, 12)));
  EXPECT_TRUE(apply("skewX(45)", {0, 10}).isApprox(Eigen::Vector2d(10, 10)));
  EXPECT_TRUE(apply("skewY(45)", {10, 0}).isApprox(Eigen::Vector2d(10, 10)));
  EXPECT_NE(ErrorOf([] { ParseSvgTransform("foo(1)"); }).find("unknown transform 'foo'"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSvgTransform("translate(1,2,3)"); }).find("does not take 3"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSvgTransform("scale(2"); }).find("expected ')'"), std::string::npos);
}

TEST(SvgPathTest, LinesAbsoluteRelativeAndClose) {
  const Polyline line = Single(FlattenSvgPath("M10 10 L20 10 l0 10 H5 h-5 V0 v5 Z", kIdentity, 1));
  const Polyline expected = {{10, 10}, {20, 10}, {20, 20}, {5, 20},
                             {0, 20},  {0, 0},   {0, 5},   {10, 10}};
  ASSERT_EQ(line.size(), expected.size());
  for (size_t k = 0; k < line.size(); ++k) EXPECT_EQ(line[k], expected[k]) << k;
  // Implicit linetos after a moveto, relative to the previous point.
  const Polyline implicit = Single(FlattenSvgPath("m 1 1 2 2 3 3", kIdentity, 1));
  EXPECT_EQ(implicit, (Polyline{{1, 1}, {3, 3}, {6, 6}}));
  // Subpaths; a drawing command after Z starts at the closed subpath's start.
  const auto lines = FlattenSvgPath("M0 0 L10 0 Z L 0 10 M20 0 L30 0", kIdentity, 1);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], (Polyline{{0, 0}, {10, 0}, {0, 0}}));
  EXPECT_EQ(lines[1], (Polyline{{0, 0}, {0, 10}}));
  EXPECT_EQ(lines[2], (Polyline{{20, 0}, {30, 0}}));
}

TEST(SvgPathTest, CubicsWithSmoothReflectionFollowTheExactCurve) {
  ExpectFollowsCurve(Single(FlattenSvgPath("M0 0 C 0 100 100 100 100 0", kIdentity, kTolerance)),
                     Cubic({0, 0}, {0, 100}, {100, 100}, {100, 0}), kTolerance);
  // Relative c, then s reflecting the last control point (50, 50) about (50, 0).
  const Curve expected = Join(Cubic({0, 0}, {0, 50}, {50, 50}, {50, 0}),
                              Cubic({50, 0}, {50, -50}, {100, -50}, {100, 0}));
  ExpectFollowsCurve(
      Single(FlattenSvgPath("M0 0 c 0 50 50 50 50 0 s 50 -50 50 0", kIdentity, kTolerance)),
      expected, kTolerance);
  ExpectFollowsCurve(
      Single(FlattenSvgPath("M0 0 C 0 50 50 50 50 0 S 100 -50 100 0", kIdentity, kTolerance)),
      expected, kTolerance);
  // S after a line: its first control point is the current point.
  ExpectFollowsCurve(Single(FlattenSvgPath("M0 0 S 100 100 100 0", kIdentity, kTolerance)),
                     Cubic({0, 0}, {0, 0}, {100, 100}, {100, 0}), kTolerance);
}

TEST(SvgPathTest, QuadraticsWithSmoothReflectionFollowTheExactCurve) {
  const Curve expected =
      Join(Quad({0, 0}, {50, 100}, {100, 0}), Quad({100, 0}, {150, -100}, {200, 0}));
  ExpectFollowsCurve(Single(FlattenSvgPath("M0 0 Q 50 100 100 0 T 200 0", kIdentity, kTolerance)),
                     expected, kTolerance);
  ExpectFollowsCurve(Single(FlattenSvgPath("M0 0 q 50 100 100 0 t 100 0", kIdentity, kTolerance)),
                     expected, kTolerance);
}

TEST(SvgPathTest, TransformIsAppliedBeforeFlattening) {
  // Scaled by 4, the curve needs about twice the points for the same
  // tolerance in the target space.
  const Eigen::Affine2d scale4(Eigen::Scaling(4.0, 4.0));
  const Polyline small =
      Single(FlattenSvgPath("M0 0 C 0 100 100 100 100 0", kIdentity, kTolerance));
  const Polyline large = Single(FlattenSvgPath("M0 0 C 0 100 100 100 100 0", scale4, kTolerance));
  ExpectFollowsCurve(large, Cubic({0, 0}, {0, 400}, {400, 400}, {400, 0}), kTolerance);
  EXPECT_NEAR(static_cast<double>(large.size() - 1) / (small.size() - 1), 2.0, 0.1);
}

TEST(SvgPathTest, CircularArcsByFlags) {
  // Endpoints (0, 0) and (100, 0), radius 100: centres (50, +-86.6); the
  // small arc spans 60 degrees, the large one 300.
  const double h = 100 * std::sqrt(3.0) / 2;
  struct Case {
    const char* d;
    double centre_y, angle, lowest_y;
  } cases[] = {
      {"M0 0 A 100 100 0 0 1 100 0", h, kPi / 3, h - 100},
      {"M0 0 A 100 100 0 1 1 100 0", -h, 5 * kPi / 3, -h - 100},
      {"M0 0 A 100 100 0 0 0 100 0", -h, kPi / 3, 0},
      {"M0 0 A 100 100 0 1 0 100 0", h, 5 * kPi / 3, 0},
  };
  for (const Case& c : cases) {
    const Polyline line = Single(FlattenSvgPath(c.d, kIdentity, kTolerance));
    const Eigen::Vector2d centre(50, c.centre_y);
    double length = 0, lowest = 0;
    for (size_t k = 0; k < line.size(); ++k) {
      EXPECT_NEAR((line[k] - centre).norm(), 100, 1e-9) << c.d;
      if (k > 0) {
        length += (line[k] - line[k - 1]).norm();
        EXPECT_GE(((line[k] + line[k - 1]) / 2 - centre).norm(), 100 - kTolerance) << c.d;
      }
      lowest = std::min(lowest, line[k].y());
    }
    EXPECT_NEAR(length, 100 * c.angle, 100 * c.angle * 2e-3) << c.d;
    EXPECT_NEAR(lowest, c.lowest_y, kTolerance) << c.d;
  }
  // Radii too small are scaled up: a half circle of radius 50.
  const Polyline half = Single(FlattenSvgPath("M0 0 a 1 1 0 0 1 100 0", kIdentity, kTolerance));
  for (const Eigen::Vector2d& p : half) EXPECT_NEAR((p - Eigen::Vector2d(50, 0)).norm(), 50, 1e-9);
}

TEST(SvgPathTest, RotatedEllipticalArcFollowsTheEllipse) {
  const Eigen::Vector2d centre(100, 100);
  const Eigen::Rotation2Dd axes(30 * kPi / 180);
  const auto on_ellipse = [&](double theta) -> Eigen::Vector2d {
    return centre + axes * Eigen::Vector2d(60 * std::cos(theta), 30 * std::sin(theta));
  };
  const Eigen::Vector2d a = on_ellipse(0.3), b = on_ellipse(2.0);
  char d[200];
  std::snprintf(d, sizeof(d), "M %.17g %.17g A 60 30 30 0 1 %.17g %.17g", a.x(), a.y(), b.x(),
                b.y());
  ExpectFollowsCurve(
      Single(FlattenSvgPath(d, kIdentity, kTolerance)),
      [&](double t) { return on_ellipse(0.3 + 1.7 * t); }, kTolerance);
}

TEST(SvgPathTest, PackedArcFlags) {
  const Polyline line = Single(FlattenSvgPath("M0 0a5 5 0 1110 10", kIdentity, kTolerance));
  EXPECT_LT((line.back() - Eigen::Vector2d(10, 10)).norm(), 1e-12);
}

TEST(SvgPathTest, SyntaxErrorsSayWhatAndWhere) {
  const auto error = [](const char* d) {
    return ErrorOf([d] { FlattenSvgPath(d, kIdentity, kTolerance); });
  };
  EXPECT_NE(error("L 1 1").find("must start with a moveto"), std::string::npos);
  EXPECT_NE(error("M 1").find("expected a number at character 4 (the end)"), std::string::npos);
  EXPECT_NE(error("M 1 1 X 2").find("unknown path command 'X' at character 7"), std::string::npos);
  EXPECT_NE(error("M 0 0 L 1e999 0").find("out of range"), std::string::npos);
  EXPECT_NE(error("M 0 0 A 1 1 0 2 0 5 5").find("arc flag"), std::string::npos);
  EXPECT_NE(error("M 0 0 L 1 1 Z 2 2").find("expected a path command"), std::string::npos);
  EXPECT_NE(error("M 0 0 L 1 nan").find("expected a number"), std::string::npos);
}

}  // namespace
}  // namespace sylva
