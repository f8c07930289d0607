#include "simulate/trace_index.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// Cells are this many join distances wide.
constexpr double kCellsPerJoinDistance = 2.0;
// Edges are sampled this many times per join distance.
constexpr double kSamplesPerJoinDistance = 2.0;
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
  // A long one: every point within the join distance of the edge lies within
  // `reach` of one of the samples, which are at most `spacing` apart.
  const double spacing = join_distance_ / kSamplesPerJoinDistance;
  const double reach = join_distance_ + spacing / 2;
  const int samples = static_cast<int>(std::ceil((b - a).norm() / spacing)) + 1;
  if (stamps_.empty()) stamps_.assign(heads_.size(), 0);
  const int32_t serial = ++serial_;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(s) / (samples - 1));
    ForEachCell(p.array() - reach, p.array() + reach, [&](int64_t cell) {
      if (stamps_[cell] == serial) return;
      stamps_[cell] = serial;
      Insert(cell, child);
    });
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
