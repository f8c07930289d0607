// Nearest-neighbour queries on a fixed set of 3D points, bucketed in a
// uniform grid over their bounds (a dense array of cells, each cell's
// points contiguous). Exact; the cell size adapts to the points' spread.
#ifndef SYLVA_CORE_GEOMETRY_POINT_GRID_H_
#define SYLVA_CORE_GEOMETRY_POINT_GRID_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

class PointGrid {
 public:
  // The points are copied. `cell_size` (world units) 0 = automatic; it is
  // enlarged where the bounds would need more than max(2^20, 4 x points)
  // cells.
  explicit PointGrid(std::vector<Eigen::Vector3d> points, double cell_size = 0.0);

  // Index of the point nearest to `query` within `max_distance` (world
  // units; infinity = any), or -1; `distance` (optional) receives it.
  int Nearest(const Eigen::Vector3d& query, double max_distance, double* distance = nullptr) const;

  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  double cell_size() const { return cell_size_; }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / cell_size_).array().floor().cast<int>();
  }
  // Index of a cell within cell_min_ .. cell_max_.
  int64_t CellIndex(const Eigen::Vector3i& c) const {
    const Eigen::Vector3i d = c - cell_min_;
    return (int64_t{d.z()} * dims_.y() + d.y()) * dims_.x() + d.x();
  }
  static double AutomaticCellSize(const Box3d& box, size_t num_points);
  void VisitShell(const Eigen::Vector3i& center, int ring, const Eigen::Vector3d& query, int* best,
                  double* best_distance) const;

  std::vector<Eigen::Vector3d> points_;
  double cell_size_ = 1.0;
  Box3d box_;
  Eigen::Vector3i cell_min_ = Eigen::Vector3i::Zero();  // cells spanned by box_
  Eigen::Vector3i cell_max_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();  // cell_max_ - cell_min_ + 1
  std::vector<int> cell_start_;   // cell k's points: cell_points_[cell_start_[k], [k + 1])
  std::vector<int> cell_points_;  // point indices, by cell, increasing within a cell
};

}  // namespace sylva

#endif  // SYLVA_CORE_GEOMETRY_POINT_GRID_H_
