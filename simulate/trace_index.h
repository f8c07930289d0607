// Edges of particle traces, bucketed for "is there one within the join
// distance of this point?" queries, so that a particle flowing along the path
// of particles that went before it joins their trace instead of laying a
// second one beside it. Internal to simulate/.
#ifndef SYLVA_SIMULATE_TRACE_INDEX_H_
#define SYLVA_SIMULATE_TRACE_INDEX_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/geometry/polyline.h"
#include "simulate/trace_graph.h"

namespace sylva {

class TraceIndex {
 public:
  // Covers the box [lower, upper] (sim frame, voxels); edges outside it are
  // not indexed, and points outside it find none. `join_distance` > 0, in
  // voxels.
  TraceIndex(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, double join_distance);

  // Indexes the edge from `child` to its parent (its geometry is read from
  // `graph` when queried, so a later split of the edge stays covered as
  // long as the new part is added too).
  void AddEdge(const TraceGraph& graph, int child);
  // Indexes every edge upstream of `node`, and its own.
  void AddSubtree(const TraceGraph& graph, int node);

  // Indexes the edges made since the last call (graph.EdgesInOrder()).
  void AddNewEdges(const TraceGraph& graph);

  // The indexed edge nearest to `point` within the join distance, as its
  // child node (ties: the lowest), and the nearest point on it; false if
  // none. Edges whose nearest point is their free tip (a seeding node) are
  // skipped, and so are those for which accept(child) is false. Const and
  // thread-safe.
  bool Nearest(const TraceGraph& graph, const Eigen::Vector3d& point, int* child,
               Eigen::Vector3d* point_on_edge) const {
    return Nearest(
        graph, point, [](int) { return true; }, child, point_on_edge);
  }
  template <typename Accept>
  bool Nearest(const TraceGraph& graph, const Eigen::Vector3d& point, const Accept& accept,
               int* child, Eigen::Vector3d* point_on_edge) const;

 private:
  void Insert(int64_t cell, int child);
  int64_t CellIndex(const Eigen::Vector3i& cell) const {
    return (int64_t{cell.z()} * dims_.y() + cell.y()) * dims_.x() + cell.x();
  }
  bool Inside(const Eigen::Vector3i& cell) const {
    return (cell.array() >= 0).all() && (cell.array() < dims_.array()).all();
  }
  // May lie outside the grid (see Inside), by at most one cell per axis.
  Eigen::Vector3i CellOf(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d cell = ((point - lower_) / cell_size_).array().floor();
    return cell.cwiseMax(-1.0).cwiseMin(dims_.cast<double>()).cast<int>();
  }

  Eigen::Vector3d lower_;
  double join_distance_;
  double cell_size_;
  Eigen::Vector3i dims_;
  // Per cell, the child nodes of the edges that may pass within the join
  // distance of it: a linked list through entries_ (-1 ends it), so that an
  // empty grid is one small array.
  struct Entry {
    int32_t child;
    int32_t next;
  };
  std::vector<int32_t> heads_;
  std::vector<Entry> entries_;
  size_t edges_indexed_ = 0;  // of graph.EdgesInOrder(), by AddNewEdges
};

template <typename Accept>
bool TraceIndex::Nearest(const TraceGraph& graph, const Eigen::Vector3d& point,
                         const Accept& accept, int* child, Eigen::Vector3d* point_on_edge) const {
  const Eigen::Vector3i cell = CellOf(point);
  if (!Inside(cell)) return false;
  double best2 = join_distance_ * join_distance_;
  int best = -1;
  for (int entry = heads_[CellIndex(cell)]; entry >= 0; entry = entries_[entry].next) {
    const int candidate = entries_[entry].child;
    const Eigen::Vector3d a = graph.Position(candidate);
    const Eigen::Vector3d b = graph.Position(graph.Parent(candidate));
    double t;
    const double d2 = SegmentDistance2(point, a, b, &t);
    if (!(d2 < best2 || (d2 == best2 && best >= 0 && candidate < best))) continue;
    // Not at the free end of a tip edge: a seeding node carries exactly one
    // particle, so nothing joins there (the particle may join further on).
    if (t == 0.0 && graph.IsTip(candidate)) continue;
    if (!accept(candidate)) continue;
    best2 = d2;
    best = candidate;
    *point_on_edge = a + t * (b - a);
  }
  if (best < 0) return false;
  *child = best;
  return true;
}

}  // namespace sylva

#endif  // SYLVA_SIMULATE_TRACE_INDEX_H_
