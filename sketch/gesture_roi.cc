#include "sketch/gesture_roi.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/util/check.h"

namespace sylva {
namespace {

// Candidate exponents n of the supertoroid fit.
constexpr double kFitExponents[] = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9,
                                    1.0, 1.2, 1.4, 1.6, 1.8, 2.0};
// Height slices of the ROI fit.
constexpr int kFitSlices = 8;
// Horizontal radii differing more than this ratio are taken as contours
// drawn on one plane.
constexpr double kRevolutionRatio = 0.5;

// Centre and axis slope from the mean position of height slices.
void FitAxis(const std::vector<Eigen::Vector3d>& points, Supertoroid* s) {
  std::vector<Eigen::Vector3d> means;
  for (int b = 0; b < kFitSlices; ++b) {
    const double lo = s->center.z() - s->az + 2 * s->az * b / kFitSlices;
    const double hi = lo + 2 * s->az / kFitSlices;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (const Eigen::Vector3d& p : points) {
      if (p.z() >= lo && (p.z() < hi || b == kFitSlices - 1)) sum += p, ++count;
    }
    if (count > 0) means.push_back(sum / count);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : means) mean += m;
  mean /= static_cast<double>(means.size());
  double szz = 0;
  Eigen::Vector2d sxz = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& m : means) {
    szz += (m.z() - mean.z()) * (m.z() - mean.z());
    sxz += (m.head<2>() - mean.head<2>()) * (m.z() - mean.z());
  }
  s->slope = szz > 0 ? Eigen::Vector2d(sxz / szz) : Eigen::Vector2d::Zero();
  s->center.head<2>() = mean.head<2>() + s->slope * (s->center.z() - mean.z());
}

// The exponent n whose surface passes nearest the points.
double FitExponent(const std::vector<Eigen::Vector3d>& points, Supertoroid s) {
  double best = 1.0, best_error = std::numeric_limits<double>::infinity();
  for (double n : kFitExponents) {
    s.n = n;
    double error = 0;
    for (const Eigen::Vector3d& p : points) {
      error += std::pow(std::pow(s.InsideOutside(p), n / 2) - 1.0, 2);
    }
    if (error < best_error) best_error = error, best = n;
  }
  return best;
}

}  // namespace

double Supertoroid::InsideOutside(const Eigen::Vector3d& p) const {
  const double h = p.z() - center.z();
  const double dx = (p.x() - center.x() - slope.x() * h) / ax;
  const double dy = (p.y() - center.y() - slope.y() * h) / ay;
  const double rho = std::pow(std::pow(std::abs(dx), 2 / e) + std::pow(std::abs(dy), 2 / e), e / 2);
  return std::pow(std::abs(rho - alpha), 2 / n) + std::pow(std::abs(h / az), 2 / n);
}

Eigen::Vector3d Supertoroid::AxisAt(double z) const {
  const double h = z - center.z();
  return {center.x() + slope.x() * h, center.y() + slope.y() * h, z};
}

Supertoroid FitSupertoroid(const std::vector<Eigen::Vector3d>& points, bool enclose,
                           const GestureTreeOptions& options) {
  SYLVA_CHECK(!points.empty());
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double height = std::max(hi.z() - lo.z(), 1e-9);
  Supertoroid s;
  s.e = options.roi_e;
  s.alpha = options.roi_alpha;
  s.n = options.roi_n > 0 ? options.roi_n : 1.0;
  if (enclose) {  // around the gestures, a little above and beside them
    s.center = 0.5 * (lo + hi);
    s.center.z() += options.roi_lift * height;
    s.az = 0.5 * options.roi_margin * height;
    const Eigen::Vector3d half = 0.5 * options.roi_margin * (hi - lo);
    s.ax = std::max(half.x(), options.roi_min_width * height) / (1 + s.alpha);
    s.ay = std::max(half.y(), options.roi_min_width * height) / (1 + s.alpha);
    return s;
  }
  s.center.z() = 0.5 * (lo.z() + hi.z());
  s.az = 0.5 * height;
  FitAxis(points, &s);
  double rx = 0, ry = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d axis = s.AxisAt(p.z());
    rx = std::max(rx, std::abs(p.x() - axis.x()));
    ry = std::max(ry, std::abs(p.y() - axis.y()));
  }
  // Two contours drawn on one plane say nothing of the depth: a region of
  // revolution then (as sketch_views.h assumes of one drawing).
  if (rx < kRevolutionRatio * ry || ry < kRevolutionRatio * rx) rx = ry = std::max(rx, ry);
  s.ax = std::max(rx, 1e-9) / (1 + s.alpha);
  s.ay = std::max(ry, 1e-9) / (1 + s.alpha);
  if (options.roi_n <= 0) s.n = FitExponent(points, s);
  return s;
}

}  // namespace sylva
