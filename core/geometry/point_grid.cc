#include "core/geometry/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

PointGrid::PointGrid(std::vector<Eigen::Vector3d> points, double cell_size)
    : points_(std::move(points)) {
  for (const auto& p : points_) box_.extend(p);
  if (cell_size > 0) {
    cell_size_ = cell_size;
  } else if (!points_.empty()) {
    // About two points per cell for a set spread over the box's volume.
    const double volume = std::max(box_.volume(), 1e-30);
    cell_size_ = std::max(std::cbrt(volume / points_.size()) * 1.5,
                          box_.diagonal().norm() * 1e-6 + 1e-12);
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    cells_[Key(Cell(points_[i]))].push_back(static_cast<int>(i));
  }
}

int64_t PointGrid::Key(const Eigen::Vector3i& c) {
  return (int64_t{c.x()} * 73856093) ^ (int64_t{c.y()} * 19349663) ^ (int64_t{c.z()} * 83492791);
}

void PointGrid::VisitShell(const Eigen::Vector3i& center, int ring, const Eigen::Vector3d& query,
                           int* best, double* best_distance) const {
  for (int dz = -ring; dz <= ring; ++dz) {
    for (int dy = -ring; dy <= ring; ++dy) {
      for (int dx = -ring; dx <= ring; ++dx) {
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
  const double reach = std::min(max_distance, box_.exteriorDistance(query) + box_.diagonal().norm());
  const int max_ring = static_cast<int>(std::ceil(reach / cell_size_)) + 1;
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int ring = 0; ring <= max_ring; ++ring) {
    // Points in ring r are at least (r - 1) cells away.
    if (ring > 0 && (ring - 1) * cell_size_ > best_distance) break;
    VisitShell(center, ring, query, &best, &best_distance);
  }
  if (best >= 0 && best_distance > max_distance) best = -1;
  if (distance != nullptr) *distance = best >= 0 ? best_distance : max_distance;
  return best;
}

}  // namespace sylva
