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
  // The cells of the edge's bounds grown by the join distance that the edge
  // crosses once they are grown by the join distance too (a point of the
  // cell within the join distance of the edge is within it along each axis;
  // the slabs a little wider, for rounding).
  const Eigen::Vector3i lo = CellOf(a.cwiseMin(b).array() - join_distance_).cwiseMax(0);
  const Eigen::Vector3i hi =
      CellOf(a.cwiseMax(b).array() + join_distance_).cwiseMin(dims_ - Eigen::Vector3i::Ones());
  const Eigen::Vector3d along = b - a;
  const double grow = join_distance_ + 1e-9 * cell_size_;
  const Eigen::Vector3d inverse = along.cwiseInverse();
  // The parameters t in [0, 1] where the edge is within a cell's slab along
  // one axis, narrowed down the axes; false if none.
  const auto crosses = [&](int axis, int cell, double* t0, double* t1) {
    const double low = lower_[axis] + cell_size_ * cell - grow - a[axis];
    const double high = low + cell_size_ + 2 * grow;
    if (along[axis] == 0.0) return low <= 0.0 && 0.0 <= high;
    const double enter = low * inverse[axis], leave = high * inverse[axis];
    *t0 = std::max(*t0, std::min(enter, leave));
    *t1 = std::min(*t1, std::max(enter, leave));
    return *t0 <= *t1;
  };
  for (int z = lo.z(); z <= hi.z(); ++z) {
    double z0 = 0.0, z1 = 1.0;
    if (!crosses(2, z, &z0, &z1)) continue;
    for (int y = lo.y(); y <= hi.y(); ++y) {
      double y0 = z0, y1 = z1;
      if (!crosses(1, y, &y0, &y1)) continue;
      for (int x = lo.x(); x <= hi.x(); ++x) {
        double x0 = y0, x1 = y1;
        if (crosses(0, x, &x0, &x1)) Insert(CellIndex({x, y, z}), child);
      }
    }
  }
}

void TraceIndex::Insert(int64_t cell, int child) {
  entries_.push_back({child, heads_[cell]});
  heads_[cell] = static_cast<int32_t>(entries_.size() - 1);
}

void TraceIndex::AddSubtree(const TraceGraph& graph, int node) {
  graph.ForEachEdgeUpstream(node, [&](int child) { AddEdge(graph, child); });
}

void TraceIndex::AddNewEdges(const TraceGraph& graph) {
  const std::vector<int32_t>& edges = graph.EdgesInOrder();
  for (; edges_indexed_ < edges.size(); ++edges_indexed_) AddEdge(graph, edges[edges_indexed_]);
}

}  // namespace sylva
