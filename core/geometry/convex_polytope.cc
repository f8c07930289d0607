#include "core/geometry/convex_polytope.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Relative tolerance (times the initial box size) for points on a plane.
constexpr double kRelativeTolerance = 1e-10;

}  // namespace

ConvexPolytope::ConvexPolytope(const Box3d& box) : scale_(box.diagonal().norm()) {
  SYLVA_CHECK(!box.isEmpty());
  using Corner = Box3d::CornerType;
  const auto c = [&](Corner corner) { return box.corner(corner); };
  faces_ = {
      {c(Box3d::BottomLeftFloor), c(Box3d::TopLeftFloor), c(Box3d::TopRightFloor),
       c(Box3d::BottomRightFloor)},
      {c(Box3d::BottomLeftCeil), c(Box3d::BottomRightCeil), c(Box3d::TopRightCeil),
       c(Box3d::TopLeftCeil)},
      {c(Box3d::BottomLeftFloor), c(Box3d::BottomRightFloor), c(Box3d::BottomRightCeil),
       c(Box3d::BottomLeftCeil)},
      {c(Box3d::TopLeftFloor), c(Box3d::TopLeftCeil), c(Box3d::TopRightCeil),
       c(Box3d::TopRightFloor)},
      {c(Box3d::BottomLeftFloor), c(Box3d::BottomLeftCeil), c(Box3d::TopLeftCeil),
       c(Box3d::TopLeftFloor)},
      {c(Box3d::BottomRightFloor), c(Box3d::TopRightFloor), c(Box3d::TopRightCeil),
       c(Box3d::BottomRightCeil)},
  };
}

void ConvexPolytope::Clip(const Eigen::Vector3d& normal, double offset) {
  const double norm = normal.norm();
  SYLVA_CHECK(norm > 0);
  const Eigen::Vector3d n = normal / norm;
  const double d = offset / norm;
  const double tolerance = kRelativeTolerance * scale_;
  std::vector<Polygon> clipped_faces;
  std::vector<Eigen::Vector3d> cut_points;
  for (const Polygon& face : faces_) {
    // Sutherland-Hodgman against one plane.
    Polygon kept;
    for (size_t i = 0; i < face.size(); ++i) {
      const Eigen::Vector3d& a = face[i];
      const Eigen::Vector3d& b = face[(i + 1) % face.size()];
      const double da = n.dot(a) + d, db = n.dot(b) + d;
      if (da >= -tolerance) kept.push_back(a);
      if (std::abs(da) <= tolerance) cut_points.push_back(a);
      if ((da > tolerance && db < -tolerance) || (da < -tolerance && db > tolerance)) {
        const Eigen::Vector3d p = a + (b - a) * (da / (da - db));
        kept.push_back(p);
        cut_points.push_back(p);
      }
    }
    if (kept.size() >= 3) clipped_faces.push_back(std::move(kept));
  }
  faces_ = std::move(clipped_faces);
  if (faces_.empty()) return;
  Polygon cap = OrderCapPolygon(cut_points, n, 10 * tolerance);
  if (cap.size() >= 3) faces_.push_back(std::move(cap));
}

ConvexPolytope::Polygon ConvexPolytope::OrderCapPolygon(const std::vector<Eigen::Vector3d>& points,
                                                        const Eigen::Vector3d& normal,
                                                        double merge_distance) {
  Polygon unique;
  for (const Eigen::Vector3d& p : points) {
    const bool duplicate = std::any_of(unique.begin(), unique.end(), [&](const auto& q) {
      return (p - q).norm() <= merge_distance;
    });
    if (!duplicate) unique.push_back(p);
  }
  if (unique.size() < 3) return {};
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : unique) centroid += p;
  centroid /= unique.size();
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d v = normal.cross(u);
  std::sort(unique.begin(), unique.end(), [&](const auto& a, const auto& b) {
    return std::atan2((a - centroid).dot(v), (a - centroid).dot(u)) <
           std::atan2((b - centroid).dot(v), (b - centroid).dot(u));
  });
  return unique;
}

std::vector<Eigen::Vector3d> ConvexPolytope::Vertices() const {
  std::vector<Eigen::Vector3d> vertices;
  for (const Polygon& face : faces_) vertices.insert(vertices.end(), face.begin(), face.end());
  return vertices;
}

Box3d ConvexPolytope::Bounds() const {
  Box3d box;
  for (const Polygon& face : faces_)
    for (const auto& p : face) box.extend(p);
  return box;
}

}  // namespace sylva
