// Axis-aligned boxes and ray-box clipping.
#ifndef SYLVA_CORE_GEOMETRY_BOX_H_
#define SYLVA_CORE_GEOMETRY_BOX_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/geometry/rigid3.h"

namespace sylva {

using Box3d = Eigen::AlignedBox3d;

// Clips `ray` to `box` (slab method). On a hit, returns true and the parameter
// interval [*t_enter, *t_exit] with t_enter >= ray.t_min.
bool ClipRayToBox(const Ray3d& ray, const Box3d& box, double* t_enter, double* t_exit);

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_BOX_H_
