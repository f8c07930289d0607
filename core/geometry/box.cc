#include "core/geometry/box.h"

#include <algorithm>
#include <limits>

namespace sylva {

bool ClipRayToBox(const Ray3d& ray, const Box3d& box, double* t_enter, double* t_exit) {
  double t0 = ray.t_min;
  double t1 = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double d = ray.direction[axis];
    const double o = ray.origin[axis];
    if (d == 0.0) {
      if (o < box.min()[axis] || o > box.max()[axis]) return false;
      continue;
    }
    double ta = (box.min()[axis] - o) / d;
    double tb = (box.max()[axis] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  *t_enter = t0;
  *t_exit = t1;
  return true;
}

}  // namespace sylva
