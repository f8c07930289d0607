// Open uniform cubic B-splines (thesis 5.2.1, eq. 5.8-5.14).
//
// A branch axis is smoothed by the uniform cubic B-spline whose control
// points are the axis' skeleton nodes P_0..P_{n-1}. Segment k (k = 0..n-2)
// is the matrix form of eq. 5.14,
//
//   C_k(t) = [t^3 t^2 t 1] (1/6) [-1  3 -3  1] [P_{k-1}]
//                                [ 3 -6  3  0] [P_k    ]      t in [0, 1],
//                                [-3  0  3  0] [P_{k+1}]
//                                [ 1  4  1  0] [P_{k+2}]
//
// and the global parameter u in [0, n-1] runs over segment floor(u) with
// t = u - floor(u), so u = k lies at (or, inside the axis, near) node k.
//
// Open ends: the curve must start at P_0 and end at P_{n-1}. We use
// reflected phantom points P_{-1} = 2 P_0 - P_1 and P_n = 2 P_{n-1} - P_{n-2}
// rather than repeating the end points or clamping the knots: every segment
// keeps the uniform matrix above, C(0) = P_0 and C(n-1) = P_{n-1} exactly,
// the end tangents are the end edges (C'(0) = P_1 - P_0, never zero, so
// frames are defined at the ends; a tripled end point would give C'(0) = 0),
// and the ends have zero curvature. Equally spaced collinear points give
// exactly their line, traversed at constant speed. Interior nodes are
// approximated, not interpolated (within |P_{k-1} - 2 P_k + P_{k+1}| / 6).
#ifndef SYLVA_MESH_BSPLINE_H_
#define SYLVA_MESH_BSPLINE_H_

#include <Eigen/Core>
#include <vector>

namespace sylva {

// The four cubic B-spline basis functions of one segment at t in [0, 1]:
// the weights of P_{k-1}, P_k, P_{k+1}, P_{k+2} in eq. 5.14 (the thesis'
// b_3, b_2, b_1, b_0 of eq. 5.9-5.12). They sum to one.
Eigen::Vector4d CubicBSplineBasis(double t);
// Their derivatives with respect to t (they sum to zero).
Eigen::Vector4d CubicBSplineBasisDerivative(double t);

class CubicBSpline {
 public:
  // `control_points` in any frame/unit (world units for branch axes); at
  // least 2. Throws Error otherwise.
  explicit CubicBSpline(const std::vector<Eigen::Vector3d>& control_points);

  int NumControlPoints() const { return static_cast<int>(padded_.size()) - 2; }
  int NumSegments() const { return NumControlPoints() - 1; }
  // Control point i (0..n-1), or a phantom for i = -1 and i = n.
  const Eigen::Vector3d& ControlPoint(int i) const { return padded_[i + 1]; }

  // The curve point and its derivative dC/du at u in [0, NumSegments()]
  // (clamped to that range), by the matrix form of eq. 5.14.
  Eigen::Vector3d Evaluate(double u) const;
  Eigen::Vector3d Derivative(double u) const;

  // The segment k and local t in [0, 1] that u falls in.
  void Locate(double u, int* segment, double* t) const;

 private:
  std::vector<Eigen::Vector3d> padded_;  // P_{-1}, P_0, ..., P_{n-1}, P_n
};

// Reference evaluation of the same curve by the recursive Cox-de Boor
// formula (eq. 5.8 and the N_{i,p} recursion) over the padded control points
// and the uniform knots -3, -2, ..., n + 2. Slow; for tests and benchmarks.
Eigen::Vector3d EvaluateCoxDeBoor(const CubicBSpline& spline, double u);
// dC/du the same way: N'_{j,3} = N_{j,2} - N_{j+1,2} for unit knot spacing.
Eigen::Vector3d DerivativeCoxDeBoor(const CubicBSpline& spline, double u);

}  // namespace sylva

#endif  // SYLVA_MESH_BSPLINE_H_
