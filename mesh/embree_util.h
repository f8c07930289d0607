// Small helpers shared by the Embree-based renderers of sylva_mesh
// (mesh_renderer.cc, tree_preview.cc). Private to the module: it includes
// Embree, so only .cc files of mesh/ include it, never a public header.
#ifndef SYLVA_MESH_EMBREE_UTIL_H_
#define SYLVA_MESH_EMBREE_UTIL_H_

#include <embree3/rtcore.h>

#include <Eigen/Core>

#include "core/util/check.h"

namespace sylva {

// Throws Error naming `step` if the device reports an error.
inline void CheckEmbreeDevice(RTCDevice device, const char* step) {
  const RTCError error = rtcGetDeviceError(device);
  SYLVA_CHECK(error == RTC_ERROR_NONE)
      << "Embree error " << static_cast<int>(error) << " in " << step;
}

// A ray origin + t direction for t in [tnear, tfar], every mask bit set.
inline RTCRay EmbreeRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                        float tnear, float tfar) {
  RTCRay ray;
  ray.org_x = origin.x();
  ray.org_y = origin.y();
  ray.org_z = origin.z();
  ray.dir_x = direction.x();
  ray.dir_y = direction.y();
  ray.dir_z = direction.z();
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.time = 0.0f;
  ray.mask = ~0u;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}

// EmbreeRay with an empty hit, for rtcIntersect*.
inline RTCRayHit EmbreeRayHit(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                              float tnear, float tfar) {
  RTCRayHit ray_hit;
  ray_hit.ray = EmbreeRay(origin, direction, tnear, tfar);
  ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray_hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return ray_hit;
}

}  // namespace sylva

#endif  // SYLVA_MESH_EMBREE_UTIL_H_
