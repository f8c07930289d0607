#include "simulate/neighbor_search.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/box.h"
#include "core/util/check.h"
#include "simulate/embree_neighbor_search.h"

namespace sylva {

namespace {

// Queries per parallel task.
constexpr int kQueryGrain = 256;

}  // namespace

int NeighborSearch::NearestOther(int idx, double max_distance, double* distance) const {
  SYLVA_DCHECK(points_ != nullptr && idx >= 0 && idx < static_cast<int>(points_->size()));
  return Nearest((*points_)[idx], idx, max_distance, distance);
}

void NeighborSearch::AllNearestOthers(double max_distance, std::vector<int>* nearest,
                                      std::vector<double>* distances) const {
  const int n = static_cast<int>(points_->size());
  nearest->resize(n);
  distances->resize(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, kQueryGrain),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int i = range.begin(); i < range.end(); ++i) {
                        (*nearest)[i] = NearestOther(i, max_distance, &(*distances)[i]);
                      }
                    });
}

namespace {

// The running best candidate of one query: squared distance, then index.
struct Candidate {
  double distance2;
  int idx = -1;
  bool Improves(double d2, int i) const { return d2 < distance2 || (d2 == distance2 && i < idx); }
};

double InitialDistance2(double max_distance) {
  return std::isinf(max_distance) ? std::numeric_limits<double>::infinity()
                                  : max_distance * max_distance;
}

class BruteForceNeighborSearch final : public NeighborSearch {
 public:
  void Build(const std::vector<Eigen::Vector3d>& points) override { points_ = &points; }

  int Nearest(const Eigen::Vector3d& query, int exclude_idx, double max_distance,
              double* distance) const override {
    Candidate best{InitialDistance2(max_distance)};
    const std::vector<Eigen::Vector3d>& points = *points_;
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      const double d2 = (points[i] - query).squaredNorm();
      if (i != exclude_idx && best.Improves(d2, i)) best = {d2, i};
    }
    if (distance != nullptr) *distance = best.idx >= 0 ? std::sqrt(best.distance2) : max_distance;
    return best.idx;
  }
};

// Cells per point: about one keeps both the cells visited and the points per
// cell small.
constexpr double kCellsPerPoint = 1.0;

// A dense uniform grid over the points' bounds; points sorted by cell.
class UniformGridNeighborSearch final : public NeighborSearch {
 public:
  void Build(const std::vector<Eigen::Vector3d>& points) override;
  int Nearest(const Eigen::Vector3d& query, int exclude_idx, double max_distance,
              double* distance) const override;
  // Queries in cell order, so that consecutive queries touch the same cells.
  void AllNearestOthers(double max_distance, std::vector<int>* nearest,
                        std::vector<double>* distances) const override;

 private:
  // The smallest cell edge giving at most kCellsPerPoint * n cells.
  static double CellSizeFor(const Eigen::Vector3d& extent, size_t n);
  Eigen::Vector3i CellOf(const Eigen::Vector3d& point) const;
  int64_t Linear(const Eigen::Vector3i& cell) const {
    return (int64_t{cell.z()} * dims_.y() + cell.y()) * dims_.x() + cell.x();
  }
  // Distance from `query` to the slab of cells with index `cell` along `axis`.
  double AxisGap(const Eigen::Vector3d& query, int axis, int cell) const;
  // Visits the points of cell (x, y, z), whose row (y, z) is sqrt(gap2_yz) away.
  void VisitRow(const Eigen::Vector3d& query, int x, int y, int z, double gap2_yz, int exclude_idx,
                Candidate* best) const;
  void VisitRing(const Eigen::Vector3d& query, const Eigen::Vector3i& center, int ring,
                 int exclude_idx, Candidate* best) const;

  Eigen::Vector3d lower_ = Eigen::Vector3d::Zero();  // lower corner of cell (0, 0, 0)
  double cell_size_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  std::vector<int> cell_start_;                 // per cell, into sorted_*; one extra at the end
  std::vector<int> sorted_idx_;                 // point indices, sorted by cell
  std::vector<Eigen::Vector3d> sorted_points_;  // their positions (memory locality)
};

double UniformGridNeighborSearch::CellSizeFor(const Eigen::Vector3d& extent, size_t n) {
  const double longest = extent.maxCoeff();
  if (!(longest > 0)) return 1.0;
  const double target = std::max(1.0, kCellsPerPoint * static_cast<double>(n));
  const auto num_cells = [&](double cell) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= std::max(1.0, std::ceil(extent[k] / cell));
    return cells;
  };
  // Bisection in log space: num_cells decreases as the cell grows.
  double lo = longest * 1e-7, hi = longest * (1 + 1e-9);
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = std::sqrt(lo * hi);
    (num_cells(mid) > target ? lo : hi) = mid;
  }
  return hi;
}

void UniformGridNeighborSearch::Build(const std::vector<Eigen::Vector3d>& points) {
  points_ = &points;
  Box3d bounds;
  for (const Eigen::Vector3d& p : points) bounds.extend(p);
  const Eigen::Vector3d extent =
      points.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(bounds.sizes());
  cell_size_ = CellSizeFor(extent, points.size());
  lower_ = points.empty() ? Eigen::Vector3d::Zero() : bounds.min();
  for (int k = 0; k < 3; ++k) {
    dims_[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / cell_size_)));
  }
  // Counting sort of the points by cell.
  const int64_t num_cells = int64_t{dims_.x()} * dims_.y() * dims_.z();
  cell_start_.assign(num_cells + 1, 0);
  std::vector<int64_t> cell_of_point(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    cell_of_point[i] = Linear(CellOf(points[i]));
    ++cell_start_[cell_of_point[i] + 1];
  }
  for (int64_t c = 0; c < num_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  std::vector<int> next(cell_start_.begin(), cell_start_.end() - 1);
  sorted_idx_.resize(points.size());
  sorted_points_.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const int slot = next[cell_of_point[i]]++;
    sorted_idx_[slot] = static_cast<int>(i);
    sorted_points_[slot] = points[i];
  }
}

Eigen::Vector3i UniformGridNeighborSearch::CellOf(const Eigen::Vector3d& point) const {
  Eigen::Vector3i cell;
  for (int k = 0; k < 3; ++k) {
    const double t = std::floor((point[k] - lower_[k]) / cell_size_);
    cell[k] = static_cast<int>(std::clamp(t, 0.0, static_cast<double>(dims_[k] - 1)));
  }
  return cell;
}

double UniformGridNeighborSearch::AxisGap(const Eigen::Vector3d& query, int axis, int cell) const {
  const double lo = lower_[axis] + cell * cell_size_;
  return std::max({lo - query[axis], query[axis] - (lo + cell_size_), 0.0});
}

void UniformGridNeighborSearch::VisitRow(const Eigen::Vector3d& query, int x, int y, int z,
                                         double gap2_yz, int exclude_idx, Candidate* best) const {
  const double gap_x = AxisGap(query, 0, x);
  if (gap2_yz + gap_x * gap_x > best->distance2) return;
  const int64_t c = Linear({x, y, z});
  for (int slot = cell_start_[c]; slot < cell_start_[c + 1]; ++slot) {
    const double d2 = (sorted_points_[slot] - query).squaredNorm();
    const int idx = sorted_idx_[slot];
    if (idx != exclude_idx && best->Improves(d2, idx)) *best = {d2, idx};
  }
}

void UniformGridNeighborSearch::VisitRing(const Eigen::Vector3d& query,
                                          const Eigen::Vector3i& center, int ring, int exclude_idx,
                                          Candidate* best) const {
  // Cells at Chebyshev distance `ring` from `center`, clipped to the grid;
  // planes and rows farther than the best distance so far are skipped whole.
  const Eigen::Vector3i lo = (center.array() - ring).max(0);
  const Eigen::Vector3i hi = (center.array() + ring).min(dims_.array() - 1);
  for (int z = lo.z(); z <= hi.z(); ++z) {
    const double gap_z = AxisGap(query, 2, z);
    if (gap_z * gap_z > best->distance2) continue;
    for (int y = lo.y(); y <= hi.y(); ++y) {
      const double gap_y = AxisGap(query, 1, y);
      const double gap2_yz = gap_z * gap_z + gap_y * gap_y;
      if (gap2_yz > best->distance2) continue;
      const bool face = std::abs(z - center.z()) == ring || std::abs(y - center.y()) == ring;
      if (face) {
        for (int x = lo.x(); x <= hi.x(); ++x) VisitRow(query, x, y, z, gap2_yz, exclude_idx, best);
        continue;
      }
      if (center.x() - ring >= 0) {
        VisitRow(query, center.x() - ring, y, z, gap2_yz, exclude_idx, best);
      }
      if (ring > 0 && center.x() + ring < dims_.x()) {
        VisitRow(query, center.x() + ring, y, z, gap2_yz, exclude_idx, best);
      }
    }
  }
}

int UniformGridNeighborSearch::Nearest(const Eigen::Vector3d& query, int exclude_idx,
                                       double max_distance, double* distance) const {
  Candidate best{InitialDistance2(max_distance)};
  if (!sorted_idx_.empty()) {
    const Eigen::Vector3i center = CellOf(query);
    // Beyond this ring every cell has been visited.
    const int last_ring = (center.array().max(dims_.array() - 1 - center.array())).maxCoeff();
    for (int ring = 0; ring <= last_ring; ++ring) {
      // Cells of ring r are at least (r - 1) cells from the query (or from
      // its projection onto the grid, which is no farther from any point).
      const double bound = (ring - 1) * cell_size_;
      if (ring > 1 && bound * bound > best.distance2) break;
      VisitRing(query, center, ring, exclude_idx, &best);
    }
  }
  if (distance != nullptr) *distance = best.idx >= 0 ? std::sqrt(best.distance2) : max_distance;
  return best.idx;
}

void UniformGridNeighborSearch::AllNearestOthers(double max_distance, std::vector<int>* nearest,
                                                 std::vector<double>* distances) const {
  const int n = static_cast<int>(sorted_idx_.size());
  nearest->resize(n);
  distances->resize(n);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, n, kQueryGrain), [&](const tbb::blocked_range<int>& range) {
        for (int slot = range.begin(); slot < range.end(); ++slot) {
          const int i = sorted_idx_[slot];
          (*nearest)[i] = Nearest(sorted_points_[slot], i, max_distance, &(*distances)[i]);
        }
      });
}

}  // namespace

std::unique_ptr<NeighborSearch> MakeNeighborSearch(NeighborSearchKind kind) {
  switch (kind) {
    case NeighborSearchKind::kUniformGrid:
      return std::make_unique<UniformGridNeighborSearch>();
    case NeighborSearchKind::kEmbree:
      return MakeEmbreeNeighborSearch();
    case NeighborSearchKind::kBruteForce:
      return std::make_unique<BruteForceNeighborSearch>();
  }
  return nullptr;
}

}  // namespace sylva
