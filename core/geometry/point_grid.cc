#include "core/geometry/point_grid.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace sylva {

namespace {

// Cells the grid may hold: at least this many, else 4 per point.
constexpr double kMinCellBudget = 1 << 20;
constexpr double kCellsPerPoint = 4.0;

}  // namespace

PointGrid::PointGrid(std::vector<Eigen::Vector3d> points, double cell_size)
    : points_(std::move(points)) {
  if (points_.empty()) return;
  for (const auto& p : points_) box_.extend(p);
  cell_size_ = cell_size > 0 ? cell_size : AutomaticCellSize(box_, points_.size());
  const double budget = std::max(kMinCellBudget, kCellsPerPoint * points_.size());
  for (;;) {
    const Eigen::Vector3d span = box_.sizes() / cell_size_;
    const double cells = (span.x() + 2) * (span.y() + 2) * (span.z() + 2);
    if (cells <= budget) break;
    cell_size_ *= 1.01 * std::cbrt(cells / budget);
  }
  cell_min_ = Cell(box_.min());
  cell_max_ = Cell(box_.max());
  dims_ = cell_max_ - cell_min_ + Eigen::Vector3i::Ones();
  // Counting sort of the points by cell (stable: indices increase in a cell).
  cell_start_.assign(static_cast<size_t>(dims_.prod()) + 1, 0);
  std::vector<int64_t> cell_of(points_.size());
  for (size_t i = 0; i < points_.size(); ++i) {
    cell_of[i] = CellIndex(Cell(points_[i]));
    ++cell_start_[cell_of[i] + 1];
  }
  for (size_t k = 1; k < cell_start_.size(); ++k) cell_start_[k] += cell_start_[k - 1];
  cell_points_.resize(points_.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i)
    cell_points_[fill[cell_of[i]]++] = static_cast<int>(i);
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

void PointGrid::VisitShell(const Eigen::Vector3i& center, int ring, const Eigen::Vector3d& query,
                           int* best, double* best_distance) const {
  // Only the part of the shell inside the cells the points occupy, and of
  // each row of the cube only its ends unless the row lies on the shell.
  const Eigen::Vector3i lo = (cell_min_ - center).cwiseMax(-ring);
  const Eigen::Vector3i hi = (cell_max_ - center).cwiseMin(ring);
  const auto visit = [&](int dx, int dy, int dz) {
    const int64_t cell = CellIndex(center + Eigen::Vector3i(dx, dy, dz));
    for (int k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
      const int idx = cell_points_[k];
      const double d = (points_[idx] - query).norm();
      if (d < *best_distance || (d == *best_distance && idx < *best)) {
        *best_distance = d;
        *best = idx;
      }
    }
  };
  for (int dz = lo.z(); dz <= hi.z(); ++dz) {
    for (int dy = lo.y(); dy <= hi.y(); ++dy) {
      if (std::abs(dz) == ring || std::abs(dy) == ring) {
        for (int dx = lo.x(); dx <= hi.x(); ++dx) visit(dx, dy, dz);
      } else {
        if (lo.x() == -ring && hi.x() >= -ring) visit(-ring, dy, dz);
        if (hi.x() == ring && lo.x() <= ring && ring > 0) visit(ring, dy, dz);
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
