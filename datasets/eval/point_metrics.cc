#include "datasets/eval/point_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "core/geometry/box.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// Points bucketed in cubic cells; nearest-neighbour search by growing shells.
class PointHashGrid {
 public:
  explicit PointHashGrid(const std::vector<Eigen::Vector3d>& points) : points_(points) {
    Box3d box;
    for (const auto& p : points) box.extend(p);
    const double volume = std::max(box.volume(), 1e-30);
    // About two points per cell on average for a surface-like set.
    cell_size_ = std::max(std::cbrt(volume / std::max<size_t>(points.size(), 1)) * 1.5,
                          box.diagonal().norm() * 1e-6 + 1e-12);
    for (size_t i = 0; i < points.size(); ++i) cells_[Key(Cell(points[i]))].push_back(i);
    box_ = box;
  }

  double NearestDistance(const Eigen::Vector3d& query) const {
    const Eigen::Vector3i center = Cell(query);
    double best = std::numeric_limits<double>::infinity();
    // Beyond this ring every point of the set has been seen.
    const int max_ring =
        static_cast<int>(std::ceil((box_.exteriorDistance(query) + box_.diagonal().norm()) /
                                   cell_size_)) + 2;
    for (int ring = 0; ring <= max_ring; ++ring) {
      // Anything in ring r is at least (r - 1) * cell_size away.
      if (ring > 0 && (ring - 1) * cell_size_ > best) break;
      VisitRing(center, ring, query, &best);
    }
    return best;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / cell_size_).array().floor().cast<int>();
  }
  static int64_t Key(const Eigen::Vector3i& c) {
    return (int64_t{c.x()} * 73856093) ^ (int64_t{c.y()} * 19349663) ^ (int64_t{c.z()} * 83492791);
  }
  void VisitRing(const Eigen::Vector3i& center, int ring, const Eigen::Vector3d& query,
                 double* best) const {
    for (int dz = -ring; dz <= ring; ++dz)
      for (int dy = -ring; dy <= ring; ++dy)
        for (int dx = -ring; dx <= ring; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
          const Eigen::Vector3i cell = center + Eigen::Vector3i(dx, dy, dz);
          const auto it = cells_.find(Key(cell));
          if (it == cells_.end()) continue;
          for (size_t idx : it->second) {
            if (Cell(points_[idx]) != cell) continue;  // hash collision
            *best = std::min(*best, (points_[idx] - query).norm());
          }
        }
  }

  const std::vector<Eigen::Vector3d>& points_;
  double cell_size_ = 1.0;
  Box3d box_;
  std::unordered_map<int64_t, std::vector<size_t>> cells_;
};

void Directed(const std::vector<Eigen::Vector3d>& from, const PointHashGrid& to, double* mean,
              double* max) {
  double sum = 0.0;
  *max = 0.0;
  for (const auto& p : from) {
    const double d = to.NearestDistance(p);
    sum += d;
    *max = std::max(*max, d);
  }
  *mean = sum / from.size();
}

}  // namespace

PointSetDistances ComparePointSets(const std::vector<Eigen::Vector3d>& a,
                                   const std::vector<Eigen::Vector3d>& b) {
  SYLVA_CHECK(!a.empty() && !b.empty()) << "comparing an empty point set";
  const PointHashGrid grid_a(a), grid_b(b);
  PointSetDistances result;
  double max_ab, max_ba;
  Directed(a, grid_b, &result.mean_a_to_b, &max_ab);
  Directed(b, grid_a, &result.mean_b_to_a, &max_ba);
  result.chamfer = 0.5 * (result.mean_a_to_b + result.mean_b_to_a);
  result.hausdorff = std::max(max_ab, max_ba);
  return result;
}

}  // namespace sylva
