// A bounded convex polytope, clipped by half-spaces. Used to intersect camera
// frusta (e.g. the region seen inside every matte's bounding rectangle).
#ifndef SYLVA_CORE_GEOMETRY_CONVEX_POLYTOPE_H_
#define SYLVA_CORE_GEOMETRY_CONVEX_POLYTOPE_H_

#include <Eigen/Core>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

class ConvexPolytope {
 public:
  // The polytope equal to `box` (non-empty).
  explicit ConvexPolytope(const Box3d& box);

  // Keeps the part where normal . p + offset >= 0.
  void Clip(const Eigen::Vector3d& normal, double offset);

  bool IsEmpty() const { return faces_.empty(); }
  std::vector<Eigen::Vector3d> Vertices() const;
  Box3d Bounds() const;

 private:
  using Polygon = std::vector<Eigen::Vector3d>;
  // The cap polygon closing the cut: `points` on the plane, ordered around it.
  static Polygon OrderCapPolygon(const std::vector<Eigen::Vector3d>& points,
                                 const Eigen::Vector3d& normal, double merge_distance);

  std::vector<Polygon> faces_;
  double scale_;  // size of the initial box, for tolerances
};

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_CONVEX_POLYTOPE_H_
