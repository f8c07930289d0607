// Trunk strokes of a gesture tree (sketch/gesture_tree.h; Murakami et al.
// 4.1.1-4.1.3, 4.1.5, 5.2): each stroke resampled by arc length, smoothed,
// its radii inversely proportional to its speed; later strokes joined to
// the nearest point of the trunks before them and pushed off those where
// they would pierce them; and the straight trunk of silhouette-based
// modelling (4.2). Internal to sketch/gesture_*.cc.
#ifndef SYLVA_SKETCH_GESTURE_TRUNKS_H_
#define SYLVA_SKETCH_GESTURE_TRUNKS_H_

#include <Eigen/Core>
#include <vector>

#include "sketch/gesture_io.h"
#include "sketch/gesture_options.h"
#include "sketch/gesture_roi.h"

namespace sylva {
namespace gesture_internal {

struct TrunkPath {
  std::vector<Eigen::Vector3d> points;  // segments + 1
  std::vector<double> radii;            // per segment
};

// The trunks, the first one the tree's, the others joined to a point of
// one before them.
struct TrunkPlan {
  std::vector<TrunkPath> paths;
  std::vector<std::vector<double>> arc;  // arc length at each point
  // joins[t][j]: trunks starting at point j of trunk t.
  std::vector<std::vector<std::vector<int>>> joins;
  double first_length = 0;
};

// The trunk strokes resampled, smoothed, with radii from their speed
// (4.1.1, 5.2); later ones joined to the nearest trunk point and pushed off
// the earlier trunks (4.1.5), the points moved added to *pushed.
TrunkPlan PlanTrunks(const std::vector<const GestureStroke*>& strokes, bool timed,
                     const GestureTreeOptions& o, int* pushed);

// Silhouette-based modelling (4.2) without a trunk: "the axiom at an
// arbitrary point in the region": a straight trunk up the region's axis,
// from the ground (z = 0, where sylva puts a tree's base) or the region's
// bottom if lower, to the region's centre height.
GestureStroke AxisTrunk(const Supertoroid& roi);

}  // namespace gesture_internal
}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_TRUNKS_H_
