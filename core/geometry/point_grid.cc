#include "core/geometry/point_grid.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace sylva {

PointGrid::PointGrid(std::vector<Eigen::Vector3d> points, double cell_size)
    : points_(std::move(points)) {
  for (const auto& p : points_) box_.extend(p);
  if (cell_size > 0) {
    cell_size_ = cell_size;
  } else if (!points_.empty()) {
    cell_size_ = AutomaticCellSize(box_, points_.size());
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    cells_[Key(Cell(points_[i]))].push_back(static_cast<int>(i));
  }
  if (!points_.empty()) {
    cell_min_ = Cell(box_.min());
    cell_max_ = Cell(box_.max());
  }
}

double PointGrid::AutomaticCellSize(const Box3d& box, size_t num_points) {
  // The spacing of points spread over the box as a volume, an area or a
  // line, whichever is largest: a flat or linear set (a skeleton in a plane)
  // has no volume, and a volume-based size would collapse to nothing.
  Eigen::Vector3d extent = box.sizes();
  std::sort(extent.data(), extent.data() + 3, std::greater<double>());
  const double n = static_cast<double>(num_points);
  const double spacing = std::max({std::cbrt(extent[0] * extent[1] * extent[2] / n),
                                   std::sqrt(extent[0] * extent[1] / n), extent[0] / n});
  // About two points per cell; a single point (or coincident ones) gets unit cells.
  return spacing > 0 ? 1.5 * spacing : 1.0;
}

int64_t PointGrid::Key(const Eigen::Vector3i& c) {
  return (int64_t{c.x()} * 73856093) ^ (int64_t{c.y()} * 19349663) ^ (int64_t{c.z()} * 83492791);
}

void PointGrid::VisitShell(const Eigen::Vector3i& center, int ring, const Eigen::Vector3d& query,
                           int* best, double* best_distance) const {
  // Only the part of the shell inside the cells the points occupy.
  const Eigen::Vector3i lo = (cell_min_ - center).cwiseMax(-ring);
  const Eigen::Vector3i hi = (cell_max_ - center).cwiseMin(ring);
  for (int dz = lo.z(); dz <= hi.z(); ++dz) {
    for (int dy = lo.y(); dy <= hi.y(); ++dy) {
      for (int dx = lo.x(); dx <= hi.x(); ++dx) {
        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
        const Eigen::Vector3i cell = center + Eigen::Vector3i(dx, dy, dz);
        const auto it = cells_.find(Key(cell));
        if (it == cells_.end()) continue;
        for (int idx : it->second) {
          if (Cell(points_[idx]) != cell) continue;  // hash collision
          const double d = (points_[idx] - query).norm();
          if (d < *best_distance || (d == *best_distance && idx < *best)) {
            *best_distance = d;
            *best = idx;
          }
        }
      }
    }
  }
}

int PointGrid::Nearest(const Eigen::Vector3d& query, double max_distance, double* distance) const {
  if (points_.empty()) return -1;
  const Eigen::Vector3i center = Cell(query);
  // Beyond this ring every point has been seen.
  const double reach =
      std::min(max_distance, box_.exteriorDistance(query) + box_.diagonal().norm());
  const int max_ring = static_cast<int>(std::ceil(reach / cell_size_)) + 1;
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  // No point is nearer than the box. Ring r holds cells r apart in the max
  // norm, i.e. points at least (r - 1) cells away but possibly as close as
  // r / sqrt(3) cells in Euclidean distance: rings below this are empty.
  const int first_ring = std::max(0, static_cast<int>(std::floor(box_.exteriorDistance(query) /
                                                                 (cell_size_ * std::sqrt(3.0)))) -
                                         1);
  for (int ring = first_ring; ring <= max_ring; ++ring) {
    // Points in ring r are at least (r - 1) cells away.
    if (ring > 0 && (ring - 1) * cell_size_ > best_distance) break;
    VisitShell(center, ring, query, &best, &best_distance);
  }
  if (best >= 0 && best_distance > max_distance) best = -1;
  if (distance != nullptr) *distance = best >= 0 ? best_distance : max_distance;
  return best;
}

}  // namespace sylva
