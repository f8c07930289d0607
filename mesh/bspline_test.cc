#include "mesh/bspline.h"

#include <gtest/gtest.h>

#include <random>

#include "core/util/check.h"

namespace sylva {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  std::vector<Eigen::Vector3d> points(n);
  for (Eigen::Vector3d& p : points) p = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

TEST(BSplineTest, BasisIsAPartitionOfUnityOnEverySegment) {
  for (int i = 0; i <= 100; ++i) {
    const double t = i / 100.0;
    const Eigen::Vector4d b = CubicBSplineBasis(t);
    EXPECT_NEAR(b.sum(), 1.0, 1e-15) << t;
    EXPECT_GE(b.minCoeff(), 0.0) << t;
    EXPECT_NEAR(CubicBSplineBasisDerivative(t).sum(), 0.0, 1e-15) << t;
  }
  // The thesis' b_0..b_3 (eq. 5.9-5.12) are our weights in reverse order.
  const double u = 0.3;
  const Eigen::Vector4d b = CubicBSplineBasis(u);
  EXPECT_NEAR(b[3], u * u * u / 6, 1e-15);
  EXPECT_NEAR(b[2], (1 + 3 * u + 3 * u * u - 3 * u * u * u) / 6, 1e-15);
  EXPECT_NEAR(b[1], (4 - 6 * u * u + 3 * u * u * u) / 6, 1e-15);
  EXPECT_NEAR(b[0], (1 - 3 * u + 3 * u * u - u * u * u) / 6, 1e-15);
}

TEST(BSplineTest, CurveIsAnAffineCombinationOnEverySegment) {
  // Partition of unity in practice: translating the control points translates
  // the curve by the same vector at every parameter.
  const std::vector<Eigen::Vector3d> points = RandomPoints(7, 1);
  std::vector<Eigen::Vector3d> moved = points;
  const Eigen::Vector3d shift(3.0, -1.0, 0.5);
  for (Eigen::Vector3d& p : moved) p += shift;
  const CubicBSpline a(points), b(moved);
  for (double u = 0; u <= a.NumSegments(); u += 0.05) {
    EXPECT_LT((b.Evaluate(u) - a.Evaluate(u) - shift).norm(), 1e-13) << u;
    EXPECT_LT((b.Derivative(u) - a.Derivative(u)).norm(), 1e-13) << u;
  }
}

TEST(BSplineTest, CollinearEquallySpacedPointsGiveTheirLine) {
  const Eigen::Vector3d origin(1.0, 2.0, 3.0), step(0.3, -0.2, 0.5);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 6; ++i) points.push_back(origin + i * step);
  const CubicBSpline spline(points);
  ASSERT_EQ(spline.NumSegments(), 5);
  for (double u = 0; u <= 5.0; u += 0.01) {
    EXPECT_LT((spline.Evaluate(u) - (origin + u * step)).norm(), 1e-13) << u;
    EXPECT_LT((spline.Derivative(u) - step).norm(), 1e-13) << u;
  }
}

TEST(BSplineTest, EndpointsAreInterpolatedWithTheEndEdgesAsTangents) {
  const std::vector<Eigen::Vector3d> points = RandomPoints(5, 2);
  const CubicBSpline spline(points);
  EXPECT_LT((spline.Evaluate(0.0) - points.front()).norm(), 1e-14);
  EXPECT_LT((spline.Evaluate(4.0) - points.back()).norm(), 1e-14);
  EXPECT_LT((spline.Derivative(0.0) - (points[1] - points[0])).norm(), 1e-14);
  EXPECT_LT((spline.Derivative(4.0) - (points[4] - points[3])).norm(), 1e-14);
  // Outside [0, 4] the parameter is clamped.
  EXPECT_LT((spline.Evaluate(-1.0) - points.front()).norm(), 1e-14);
  EXPECT_LT((spline.Evaluate(9.0) - points.back()).norm(), 1e-14);
}

TEST(BSplineTest, TwoPointsGiveTheirSegment) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 2, 2);
  const CubicBSpline spline({a, b});
  EXPECT_EQ(spline.NumSegments(), 1);
  EXPECT_LT((spline.Evaluate(0.25) - (a + 0.25 * (b - a))).norm(), 1e-15);
}

TEST(BSplineTest, MatrixFormMatchesCoxDeBoor) {
  const std::vector<Eigen::Vector3d> points = RandomPoints(9, 3);
  const CubicBSpline spline(points);
  for (double u = 0; u <= spline.NumSegments(); u += 0.037) {
    EXPECT_LT((spline.Evaluate(u) - EvaluateCoxDeBoor(spline, u)).norm(), 1e-13) << u;
    EXPECT_LT((spline.Derivative(u) - DerivativeCoxDeBoor(spline, u)).norm(), 1e-12) << u;
  }
  EXPECT_LT((EvaluateCoxDeBoor(spline, spline.NumSegments()) - points.back()).norm(), 1e-12);
}

TEST(BSplineTest, CurveIsC2AcrossSegmentJoins) {
  const std::vector<Eigen::Vector3d> points = RandomPoints(6, 4);
  const CubicBSpline spline(points);
  const double h = 1e-7;
  for (int k = 1; k < spline.NumSegments(); ++k) {
    EXPECT_LT((spline.Evaluate(k - h) - spline.Evaluate(k + h)).norm(), 1e-6) << k;
    EXPECT_LT((spline.Derivative(k - h) - spline.Derivative(k + h)).norm(), 1e-5) << k;
    // The second derivative by differences of the derivative on either side.
    const Eigen::Vector3d left = (spline.Derivative(k) - spline.Derivative(k - 1e-4)) / 1e-4;
    const Eigen::Vector3d right = (spline.Derivative(k + 1e-4) - spline.Derivative(k)) / 1e-4;
    EXPECT_LT((left - right).norm(), 1e-2) << k;
  }
}

TEST(BSplineTest, NeedsTwoControlPoints) {
  EXPECT_THROW(CubicBSpline({Eigen::Vector3d::Zero()}), Error);
}

}  // namespace
}  // namespace sylva
