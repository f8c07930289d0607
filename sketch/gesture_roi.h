// The region of interest of a gesture tree (Murakami et al. eq. 3, 4.2):
// a supertoroid fitted to ROI strokes, or around the gestures; the
// interactive L-system of sketch/gesture_tree.h rewrites only the modules
// inside it and keeps every new segment in it.
#ifndef SYLVA_SKETCH_GESTURE_ROI_H_
#define SYLVA_SKETCH_GESTURE_ROI_H_

#include <Eigen/Core>
#include <vector>

#include "sketch/gesture_options.h"

namespace sylva {

// The supertoroid region of interest (Murakami eq. 3, with the up axis +Z):
// a point p is inside when
//   (|rho - alpha|)^(2/n) + |(p.z - center.z) / az|^(2/n) <= 1,
//   rho = (|dx / ax|^(2/e) + |dy / ay|^(2/e))^(e/2),
//   (dx, dy) = p.xy - center.xy - slope * (p.z - center.z),
// the slope (b_x, b_z of eq. 3) tilting its axis.
struct Supertoroid {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector2d slope = Eigen::Vector2d::Zero();
  double ax = 1, ay = 1, az = 1;
  double n = 1, e = 1, alpha = 0;

  double InsideOutside(const Eigen::Vector3d& p) const;  // <= 1 inside
  bool Contains(const Eigen::Vector3d& p) const { return InsideOutside(p) <= 1.0; }
  // The axis' point at height z.
  Eigen::Vector3d AxisAt(double z) const;
};

// Fits the region to ROI strokes (their points on its surface: centre and
// axis slope from the points' height slices, radii from their spread, n by
// a 1D search unless given) or, with `enclose`, around `points` (with the
// minimum width).
Supertoroid FitSupertoroid(const std::vector<Eigen::Vector3d>& points, bool enclose,
                           const GestureTreeOptions& options);

}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_ROI_H_
