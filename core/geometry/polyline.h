// Small polyline helpers shared by the 2D attractor graphs and the 3D
// particle traces: closest points on segments, Douglas-Peucker
// simplification and Hermite curves, for any fixed-size Eigen vector type.
#ifndef SYLVA_CORE_GEOMETRY_POLYLINE_H_
#define SYLVA_CORE_GEOMETRY_POLYLINE_H_

#include <Eigen/Core>
#include <algorithm>
#include <utility>
#include <vector>

namespace sylva {

// Parameter t in [0, 1] of the point of segment [a, b] closest to p (0 for
// a degenerate segment).
template <typename Vector>
double ClosestSegmentParameter(const Vector& p, const Vector& a, const Vector& b) {
  const Vector ab = b - a;
  const double length2 = ab.squaredNorm();
  return length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
}

// Squared distance from p to segment [a, b]; `t` (optional) receives the
// closest point's parameter.
template <typename Vector>
double SegmentDistance2(const Vector& p, const Vector& a, const Vector& b, double* t = nullptr) {
  const double s = ClosestSegmentParameter(p, a, b);
  if (t != nullptr) *t = s;
  return (a + s * (b - a) - p).squaredNorm();
}

// Squared distance between segments [p0, p1] and [q0, q1] (Ericson,
// Real-Time Collision Detection 5.1.9); `cp` and `cq` (optional) receive the
// closest points on each. Degenerate segments are points.
template <typename Vector>
double SegmentSegmentDistance2(const Vector& p0, const Vector& p1, const Vector& q0,
                               const Vector& q1, Vector* cp = nullptr, Vector* cq = nullptr) {
  const Vector d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-300 && e > 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else if (a > 1e-300) {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-300 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const Vector on_p = p0 + s * d1, on_q = q0 + t * d2;
  if (cp != nullptr) *cp = on_p;
  if (cq != nullptr) *cq = on_q;
  return (on_p - on_q).squaredNorm();
}

// Douglas-Peucker on a chain of `count` points, point(k) giving the k-th:
// sets keep[k] = 1 for the points kept so that every dropped point lies
// within `tolerance` of the kept polyline. The two ends are always kept;
// other entries of `keep` that are already 1 stay 1 (but do not split the
// chain). `keep` must have `count` entries.
template <typename PointAt>
void DouglasPeucker(int count, const PointAt& point, double tolerance, std::vector<char>* keep) {
  if (count <= 0) return;
  (*keep)[0] = (*keep)[count - 1] = 1;
  std::vector<std::pair<int, int>> ranges = {{0, count - 1}};
  while (!ranges.empty()) {
    const auto [first, last] = ranges.back();
    ranges.pop_back();
    const auto a = point(first);
    const auto b = point(last);
    double worst2 = tolerance * tolerance;
    int worst = -1;
    for (int k = first + 1; k < last; ++k) {
      const double d2 = SegmentDistance2(point(k), a, b);
      if (d2 > worst2) worst2 = d2, worst = k;
    }
    if (worst < 0) continue;
    (*keep)[worst] = 1;
    ranges.push_back({first, worst});
    ranges.push_back({worst, last});
  }
}

// `samples` + 1 points of the cubic Hermite curve from p0 (tangent m0) to
// p1 (tangent m1), both ends included.
template <typename Vector>
std::vector<Vector> HermiteCurve(const Vector& p0, const Vector& m0, const Vector& p1,
                                 const Vector& m1, int samples) {
  std::vector<Vector> curve;
  for (int k = 0; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples, t2 = t * t, t3 = t2 * t;
    curve.push_back((2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 +
                    (t3 - t2) * m1);
  }
  return curve;
}

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_POLYLINE_H_
