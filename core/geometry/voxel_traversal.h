// Exact traversal of the voxels a ray passes through (Amanatides & Woo 1987).
//
// Every voxel whose interior the ray crosses is visited once, in order, with
// the length of the ray inside it, so sums along rays have no sampling gaps.
// Voxel (i, j, k) covers [lo + (i, j, k) * voxel_size, lo + (i+1, j+1, k+1) *
// voxel_size) in world units, where lo is the grid's lower corner.
#ifndef SYLVA_CORE_GEOMETRY_VOXEL_TRAVERSAL_H_
#define SYLVA_CORE_GEOMETRY_VOXEL_TRAVERSAL_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/box.h"
#include "core/geometry/rigid3.h"

namespace sylva {

// A dense block of voxels: `dims` voxels of edge `voxel_size` (world units)
// starting at world position `lower_corner`.
struct VoxelBlock {
  Eigen::Vector3d lower_corner = Eigen::Vector3d::Zero();
  double voxel_size = 1.0;
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();

  Box3d WorldBox() const {
    return Box3d(lower_corner, lower_corner + voxel_size * dims.cast<double>());
  }
  Eigen::Vector3d VoxelCenter(const Eigen::Vector3i& ijk) const {
    return lower_corner + voxel_size * (ijk.cast<double>() + Eigen::Vector3d::Constant(0.5));
  }
  int64_t NumVoxels() const { return int64_t{dims.x()} * dims.y() * dims.z(); }
  // Dense index, x fastest.
  int64_t LinearIndex(const Eigen::Vector3i& ijk) const {
    return (int64_t{ijk.z()} * dims.y() + ijk.y()) * dims.x() + ijk.x();
  }
  Eigen::Vector3i VoxelFromLinear(int64_t index) const {
    const int x = static_cast<int>(index % dims.x());
    const int64_t yz = index / dims.x();
    return Eigen::Vector3i(x, static_cast<int>(yz % dims.y()), static_cast<int>(yz / dims.y()));
  }
};

// Calls visit(linear_index, length) for every voxel of `block` the ray
// crosses, in order of increasing t; `length` is in world units. Returns the
// number of voxels visited. `visit` may return void, or bool (false stops).
template <typename Visitor>
int TraverseVoxels(const VoxelBlock& block, const Ray3d& ray, Visitor&& visit) {
  double t_enter, t_exit;
  if (!ClipRayToBox(ray, block.WorldBox(), &t_enter, &t_exit)) return 0;
  if (!(t_exit > t_enter)) return 0;
  const double inv_size = 1.0 / block.voxel_size;
  // Start in the voxel containing the midpoint of the first step (robust on faces).
  const Eigen::Vector3d start =
      (ray.origin + ray.direction * t_enter - block.lower_corner) * inv_size;
  int64_t ijk[3];
  int step[3];
  double t_max[3], t_delta[3];
  int64_t stride[3] = {1, block.dims.x(), int64_t{block.dims.x()} * block.dims.y()};
  for (int a = 0; a < 3; ++a) {
    const double d = ray.direction[a];
    ijk[a] = std::clamp<int64_t>(static_cast<int64_t>(std::floor(start[a])), 0, block.dims[a] - 1);
    if (d > 0) {
      step[a] = 1;
      t_delta[a] = block.voxel_size / d;
      t_max[a] = t_enter + ((ijk[a] + 1) - start[a]) * t_delta[a];
    } else if (d < 0) {
      step[a] = -1;
      t_delta[a] = -block.voxel_size / d;
      t_max[a] = t_enter + (start[a] - ijk[a]) * t_delta[a];
    } else {
      step[a] = 0;
      t_delta[a] = std::numeric_limits<double>::infinity();
      t_max[a] = std::numeric_limits<double>::infinity();
    }
  }
  int64_t linear = ijk[0] * stride[0] + ijk[1] * stride[1] + ijk[2] * stride[2];
  double t = t_enter;
  int visited = 0;
  for (;;) {
    const int a =
        (t_max[0] < t_max[1]) ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    const double t_next = std::min(t_max[a], t_exit);
    if (t_next > t) {
      ++visited;
      if constexpr (std::is_same_v<decltype(visit(linear, t_next - t)), bool>) {
        if (!visit(linear, t_next - t)) return visited;
      } else {
        visit(linear, t_next - t);
      }
    }
    if (t_max[a] >= t_exit) return visited;
    t = t_next;
    ijk[a] += step[a];
    if (ijk[a] < 0 || ijk[a] >= block.dims[a]) return visited;
    linear += step[a] * stride[a];
    t_max[a] += t_delta[a];
  }
}

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_VOXEL_TRAVERSAL_H_
