#include "simulate/trace_index.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Cells are this many join distances wide.
constexpr double kCellsPerJoinDistance = 2.0;
// Limits the dense grid of cells (about 16^3 cells per million).
constexpr int64_t kMaxCells = int64_t{1} << 26;

}  // namespace

TraceIndex::TraceIndex(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                       double join_distance)
    : lower_(lower), join_distance_(join_distance) {
  SYLVA_CHECK(join_distance > 0);
  cell_size_ = kCellsPerJoinDistance * join_distance;
  const Eigen::Vector3d extent = (upper - lower).cwiseMax(0.0);
  // Coarser cells if the box would need too many.
  for (;;) {
    dims_ = (extent / cell_size_).array().ceil().cast<int>().max(1);
    if (int64_t{dims_.x()} * dims_.y() * dims_.z() <= kMaxCells) break;
    cell_size_ *= 2;
  }
  heads_.assign(int64_t{dims_.x()} * dims_.y() * dims_.z(), -1);
}

void TraceIndex::AddEdge(const TraceGraph& graph, int child) {
  const Eigen::Vector3d a = graph.Position(child);
  const Eigen::Vector3d b = graph.Position(graph.Parent(child));
  // A short edge: every cell its bounds, grown by the join distance, overlap.
  if ((b - a).norm() <= cell_size_) {
    AddCells(a.cwiseMin(b).array() - join_distance_, a.cwiseMax(b).array() + join_distance_, child);
    return;
  }
  // A long one: the cells of its box (grown as above) whose centre lies
  // within the join distance + half a cell's diagonal of it (a point of the
  // cell within the join distance of the edge puts its centre so near; a
  // little more, for rounding).
  const double reach = (join_distance_ + 0.5 * std::sqrt(3.0) * cell_size_) * (1 + 1e-9);
  const Eigen::Vector3d along = b - a;
  const double inverse_length2 = 1.0 / along.squaredNorm();
  const Eigen::Vector3i lo = CellOf(a.cwiseMin(b).array() - join_distance_).cwiseMax(0);
  const Eigen::Vector3i hi =
      CellOf(a.cwiseMax(b).array() + join_distance_).cwiseMin(dims_ - Eigen::Vector3i::Ones());
  for (int z = lo.z(); z <= hi.z(); ++z) {
    for (int y = lo.y(); y <= hi.y(); ++y) {
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const Eigen::Vector3d from_a =
            lower_ + cell_size_ * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5) - a;
        const double t = std::clamp(from_a.dot(along) * inverse_length2, 0.0, 1.0);
        if ((from_a - t * along).squaredNorm() <= reach * reach) {
          Insert(CellIndex({x, y, z}), child);
        }
      }
    }
  }
}

void TraceIndex::AddCells(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, int child) {
  ForEachCell(lower, upper, [&](int64_t cell) { Insert(cell, child); });
}

void TraceIndex::Insert(int64_t cell, int child) {
  entries_.push_back({child, heads_[cell]});
  heads_[cell] = static_cast<int32_t>(entries_.size() - 1);
}

template <typename Visit>
void TraceIndex::ForEachCell(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                             const Visit& visit) const {
  const Eigen::Vector3i lo = CellOf(lower).cwiseMax(0);
  const Eigen::Vector3i hi = CellOf(upper).cwiseMin(dims_ - Eigen::Vector3i::Ones());
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) visit(CellIndex({x, y, z}));
}

void TraceIndex::AddSubtree(const TraceGraph& graph, int node) {
  graph.ForEachEdgeUpstream(node, [&](int child) { AddEdge(graph, child); });
}

void TraceIndex::AddNewEdges(const TraceGraph& graph) {
  const std::vector<int32_t>& edges = graph.EdgesInOrder();
  for (; edges_indexed_ < edges.size(); ++edges_indexed_) AddEdge(graph, edges[edges_indexed_]);
}

}  // namespace sylva
