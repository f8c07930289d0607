#include "mesh/bspline.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Degree of the cubic B-spline. With uniform knots t_m = m - 3, padded
// control point j (P_{j-1}) has support [j - 3, j + 1) in the global
// parameter u, so u in [k, k + 1) is covered by P_{k-1}..P_{k+2}.
constexpr int kDegree = 3;

// N_{j,p}(u) for the uniform knots t_m = m - 3 (Cox-de Boor recursion).
double CoxDeBoorBasis(int j, int p, double u) {
  const double knot = j - 3.0;
  if (p == 0) return (u >= knot && u < knot + 1) ? 1.0 : 0.0;
  const double left = (u - knot) / p * CoxDeBoorBasis(j, p - 1, u);
  const double right = (knot + p + 1 - u) / p * CoxDeBoorBasis(j + 1, p - 1, u);
  return left + right;
}

// u clamped to the curve's range, the end taken as a limit from the left
// (the recursive basis is half-open on the right).
double ClampForCoxDeBoor(const CubicBSpline& spline, double u) {
  const double last = spline.NumSegments();
  return u >= last ? std::nextafter(last, 0.0) : std::max(u, 0.0);
}

}  // namespace

Eigen::Vector4d CubicBSplineBasis(double t) {
  const double t2 = t * t, t3 = t2 * t;
  // Rows of [t^3 t^2 t 1] times the matrix of eq. 5.14, divided by 6.
  return Eigen::Vector4d(-t3 + 3 * t2 - 3 * t + 1, 3 * t3 - 6 * t2 + 4,
                         -3 * t3 + 3 * t2 + 3 * t + 1, t3) /
         6.0;
}

Eigen::Vector4d CubicBSplineBasisDerivative(double t) {
  const double t2 = t * t;
  return Eigen::Vector4d(-3 * t2 + 6 * t - 3, 9 * t2 - 12 * t, -9 * t2 + 6 * t + 3, 3 * t2) / 6.0;
}

CubicBSpline::CubicBSpline(const std::vector<Eigen::Vector3d>& control_points) {
  SYLVA_CHECK(control_points.size() >= 2)
      << "a B-spline needs 2 control points, got " << control_points.size();
  const size_t n = control_points.size();
  padded_.reserve(n + 2);
  padded_.push_back(2 * control_points[0] - control_points[1]);
  padded_.insert(padded_.end(), control_points.begin(), control_points.end());
  padded_.push_back(2 * control_points[n - 1] - control_points[n - 2]);
}

void CubicBSpline::Locate(double u, int* segment, double* t) const {
  const double clamped = std::clamp(u, 0.0, static_cast<double>(NumSegments()));
  *segment = std::min(static_cast<int>(clamped), NumSegments() - 1);
  *t = clamped - *segment;
}

Eigen::Vector3d CubicBSpline::Evaluate(double u) const {
  int k;
  double t;
  Locate(u, &k, &t);
  const Eigen::Vector4d b = CubicBSplineBasis(t);
  // padded_[k] is P_{k-1}.
  return b[0] * padded_[k] + b[1] * padded_[k + 1] + b[2] * padded_[k + 2] + b[3] * padded_[k + 3];
}

Eigen::Vector3d CubicBSpline::Derivative(double u) const {
  int k;
  double t;
  Locate(u, &k, &t);
  const Eigen::Vector4d b = CubicBSplineBasisDerivative(t);
  return b[0] * padded_[k] + b[1] * padded_[k + 1] + b[2] * padded_[k + 2] + b[3] * padded_[k + 3];
}

Eigen::Vector3d EvaluateCoxDeBoor(const CubicBSpline& spline, double u) {
  u = ClampForCoxDeBoor(spline, u);
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int j = -1; j <= spline.NumControlPoints(); ++j) {
    point += CoxDeBoorBasis(j + 1, kDegree, u) * spline.ControlPoint(j);
  }
  return point;
}

Eigen::Vector3d DerivativeCoxDeBoor(const CubicBSpline& spline, double u) {
  u = ClampForCoxDeBoor(spline, u);
  Eigen::Vector3d derivative = Eigen::Vector3d::Zero();
  for (int j = -1; j <= spline.NumControlPoints(); ++j) {
    const double basis =
        CoxDeBoorBasis(j + 1, kDegree - 1, u) - CoxDeBoorBasis(j + 2, kDegree - 1, u);
    derivative += basis * spline.ControlPoint(j);
  }
  return derivative;
}

}  // namespace sylva
