#include "simulate/trace_graph.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {

TraceGraph::TraceGraph(const Eigen::Vector3d& root_in_sim) { AddNode(root_in_sim, 0, kRootTrace); }

int TraceGraph::AddNode(const Eigen::Vector3d& position_in_sim, int strands, int trace) {
  const int node = NumNodes();
  SYLVA_CHECK(node < std::numeric_limits<int32_t>::max())
      << "the traces exceed 2^31 nodes: use fewer particles or a larger trace_tolerance";
  positions_.push_back(position_in_sim.cast<float>());
  parents_.push_back(-1);
  strands_.push_back(strands);
  traces_of_.push_back(trace);
  first_child_.push_back(-1);
  next_sibling_.push_back(-1);
  return node;
}

void TraceGraph::SetParent(int node, int parent, bool new_edge) {
  SYLVA_DCHECK(parents_[node] < 0);
  parents_[node] = parent;
  next_sibling_[node] = first_child_[parent];
  first_child_[parent] = node;
  if (new_edge) edges_in_order_.push_back(node);
}

TraceCursor TraceGraph::StartTrace(const Eigen::Vector3d& position_in_sim, int trace) {
  SYLVA_CHECK(trace >= 0) << "trace ids are >= 0";
  TraceCursor cursor;
  cursor.trace = trace;
  cursor.last_node = AddNode(position_in_sim, 1, trace);
  cursor.anchor = position_in_sim;
  return cursor;
}

bool TraceGraph::LeavesRun(const TraceCursor& cursor, const Eigen::Vector3d& from,
                           const Eigen::Vector3d& to, double tolerance) {
  if (cursor.direction.isZero()) return false;
  if (!(tolerance > 0)) return true;  // every step
  const Eigen::Vector3d offset = to - cursor.anchor;
  const double along = offset.dot(cursor.direction);
  if (along < (from - cursor.anchor).dot(cursor.direction)) return true;  // turned back
  return offset.squaredNorm() - along * along > tolerance * tolerance;
}

void TraceGraph::StartRunIfNeeded(TraceCursor* cursor, const Eigen::Vector3d& to) {
  if (!cursor->direction.isZero()) return;
  const Eigen::Vector3d offset = to - cursor->anchor;
  const double length = offset.norm();
  if (length > 0) cursor->direction = offset / length;
}

int TraceGraph::RecordNode(TraceCursor* cursor, const Eigen::Vector3d& position_in_sim, int mass) {
  const int node = AddNode(position_in_sim, mass, cursor->trace);
  SetParent(cursor->last_node, node);
  cursor->last_node = node;
  cursor->at_seed = false;
  cursor->anchor = position_in_sim;
  cursor->direction.setZero();
  return node;
}

int TraceGraph::NodeAtPosition(TraceCursor* cursor, const Eigen::Vector3d& position_in_sim,
                               int mass) {
  if (!cursor->at_seed && cursor->anchor == position_in_sim) return cursor->last_node;
  return RecordNode(cursor, position_in_sim, mass);
}

void TraceGraph::EndTrace(const TraceCursor& cursor, int parent, int mass) {
  SetParent(cursor.last_node, parent);
  for (int node = parent; node >= 0; node = parents_[node]) strands_[node] += mass;
}

int TraceGraph::SplitEdge(int child, const Eigen::Vector3d& point_in_sim) {
  const int parent = parents_[child];
  SYLVA_CHECK(parent >= 0) << "trace node " << child << " has no edge to split";
  // Unlink child from its parent's list of children.
  int* link = &first_child_[parent];
  while (*link != child) link = &next_sibling_[*link];
  *link = next_sibling_[child];
  parents_[child] = -1;
  next_sibling_[child] = -1;
  const int middle = AddNode(point_in_sim, strands_[child], traces_of_[child]);
  SetParent(middle, parent);
  SetParent(child, middle, /*new_edge=*/false);
  return middle;
}

std::vector<char> TraceGraph::KeptNodes(double tolerance) const {
  const int n = NumNodes();
  std::vector<char> kept(n, 1);
  if (!(tolerance > 0)) return kept;
  std::vector<int> num_children(n, 0);
  for (int i = 0; i < n; ++i) {
    if (parents_[i] >= 0) ++num_children[parents_[i]];
  }
  for (int i = 0; i < n; ++i) kept[i] = (i == kRoot || num_children[i] != 1);
  std::vector<int> chain;
  std::vector<char> keep;
  for (int start = 0; start < n; ++start) {
    if (start == kRoot || !kept[start]) continue;
    // The chain from this key node up to the next key node.
    chain.assign(1, start);
    int node = parents_[start];
    while (!kept[node]) {
      chain.push_back(node);
      node = parents_[node];
    }
    chain.push_back(node);
    keep.assign(chain.size(), 0);
    DouglasPeucker(
        static_cast<int>(chain.size()),
        [&](int k) { return Eigen::Vector3d(positions_[chain[k]].cast<double>()); }, tolerance,
        &keep);
    for (size_t k = 0; k < chain.size(); ++k) {
      if (keep[k]) kept[chain[k]] = 1;
    }
  }
  return kept;
}

SkeletonGraph TraceGraph::ToSkeleton(const SimFrame& frame, const Eigen::Vector3d& root_in_world,
                                     double simplify_tolerance) const {
  const int n = NumNodes();
  for (int i = 0; i < n; ++i) {
    SYLVA_CHECK(i == kRoot || parents_[i] >= 0) << "trace node " << i << " was never linked";
  }
  const std::vector<char> kept = KeptNodes(simplify_tolerance);
  // Every kept node's nearest kept ancestor, and kept children in node order.
  std::vector<int> kept_parent(n, -1);
  std::vector<std::vector<int>> kept_children(n);
  for (int i = 0; i < n; ++i) {
    if (i == kRoot || !kept[i]) continue;
    int parent = parents_[i];
    while (!kept[parent]) parent = parents_[parent];
    kept_parent[i] = parent;
    kept_children[parent].push_back(i);
  }
  // Breadth-first from the root: parents before children.
  SkeletonGraph skeleton;
  std::vector<int> queue = {kRoot};
  std::vector<int> index_of(n, -1);
  for (size_t q = 0; q < queue.size(); ++q) {
    const int node = queue[q];
    SkeletonNode out;
    out.position =
        node == kRoot ? root_in_world : frame.WorldFromSim(positions_[node].cast<double>());
    out.parent_idx = node == kRoot ? -1 : index_of[kept_parent[node]];
    out.strands = strands_[node];
    index_of[node] = static_cast<int>(skeleton.nodes.size());
    skeleton.nodes.push_back(out);
    for (int child : kept_children[node]) queue.push_back(child);
  }
  skeleton.radius_source = "unknown";
  skeleton.AssignOrders();
  return skeleton;
}

}  // namespace sylva
