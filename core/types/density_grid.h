// A sparse grid of per-voxel opacity (the tree's "density", thesis 3.3).
//
// Wraps an openvdb::FloatGrid with its world transform, behind this light
// header so that most of sylva compiles without OpenVDB's headers (see
// density_grid_vdb.h for direct access). Conventions:
//   - voxel (i, j, k) has its centre at origin + voxel_size * (i, j, k), in
//     world units (OpenVDB's cell-centred convention);
//   - values are opacities alpha in [0, 1] of a ray crossing the voxel
//     straight through (path length = one voxel); the optical depth per voxel
//     length is -log(1 - alpha);
//   - voxels not stored (inactive) are empty (alpha = 0, the background).
// Copying a DensityGrid copies the voxels (deep copy).
#ifndef SYLVA_CORE_TYPES_DENSITY_GRID_H_
#define SYLVA_CORE_TYPES_DENSITY_GRID_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/geometry/box.h"

namespace sylva {

class DensityGrid {
 public:
  // An empty grid with unit voxels at the origin.
  DensityGrid();
  // An empty grid; `voxel_size` in world units (> 0), `origin` the world
  // position of voxel (0, 0, 0)'s centre.
  DensityGrid(double voxel_size, const Eigen::Vector3d& origin);
  ~DensityGrid();
  DensityGrid(const DensityGrid& other);
  DensityGrid& operator=(const DensityGrid& other);
  DensityGrid(DensityGrid&& other) noexcept;
  DensityGrid& operator=(DensityGrid&& other) noexcept;

  double voxel_size() const;
  const Eigen::Vector3d& origin() const;

  Eigen::Vector3d WorldFromIndex(const Eigen::Vector3d& index) const {
    return origin() + voxel_size() * index;
  }
  Eigen::Vector3d IndexFromWorld(const Eigen::Vector3d& point_in_world) const {
    return (point_in_world - origin()) / voxel_size();
  }

  // Opacity of a voxel (0 if inactive).
  float Value(const Eigen::Vector3i& ijk) const;
  // The largest opacity in the 3 x 3 x 3 voxels around the voxel nearest
  // `point_in_world` (lenient with points on a structure's surface).
  float MaxValueAround(const Eigen::Vector3d& point_in_world) const;
  // Stores an opacity (clamped to [0, 1]); values <= 0 deactivate the voxel.
  void SetValue(const Eigen::Vector3i& ijk, float alpha);

  int64_t NumActiveVoxels() const;
  bool IsEmpty() const { return NumActiveVoxels() == 0; }
  // Index bounds of active voxels (inclusive); false if empty.
  bool ActiveIndexBounds(Eigen::Vector3i* min_ijk, Eigen::Vector3i* max_ijk) const;
  // World box covering all active voxels (their full extent); empty box if none.
  Box3d ActiveWorldBounds() const;
  // Calls visit(ijk, alpha) for every active voxel, in a deterministic order.
  void ForEachActive(const std::function<void(const Eigen::Vector3i&, float)>& visit) const;
  // The opacities of the active voxels, in ForEachActive's order (a few
  // times faster than collecting them with it).
  std::vector<float> ActiveValues() const;
  // The active voxels at the given places of that order (ascending, each
  // below NumActiveVoxels()).
  std::vector<Eigen::Vector3i> ActiveVoxelsAt(const std::vector<int64_t>& places) const;
  double SumOfValues() const;

  // Free-form metadata saved with the grid (e.g. "units" -> "arbitrary").
  void SetMetadata(const std::string& key, const std::string& value);
  std::string GetMetadata(const std::string& key) const;  // "" if absent

  // Throws Error if the transform is not uniform-scale + translation or a
  // value lies outside [0, 1].
  void Check() const;

  struct Impl;  // defined in density_grid.cc; see density_grid_vdb.h
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_DENSITY_GRID_H_
