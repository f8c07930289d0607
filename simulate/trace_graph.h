// Particle traces, recorded while the particles flow, and their conversion
// into a skeleton. Internal to simulate/.
//
// Every node points to the node its particle reached next (its parent in the
// final tree, rooted at the base); `strands` is the number of seeded
// particles carried along the edge to that parent. Mass only changes at
// merges, and a merge always happens at a node of the survivor, so a node
// with children carries exactly the sum of its children's strands, and every
// tip (a seeding position) carries one.
#ifndef SYLVA_SIMULATE_TRACE_GRAPH_H_
#define SYLVA_SIMULATE_TRACE_GRAPH_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "simulate/particle_dynamics.h"

namespace sylva {

// Where one particle's trace stands: its last node and the straight run
// since then (Reumann-Witkam line simplification, done online).
struct TraceCursor {
  int trace = -1;  // the trace's id (the particle's seeding index)
  int last_node = -1;
  bool at_seed = true;  // last_node is the particle's seeding node (a tip)
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();     // last node's position, sim frame
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit; zero until the run starts
};

class TraceGraph {
 public:
  // Node 0 is the root, at `root_in_sim`.
  explicit TraceGraph(const Eigen::Vector3d& root_in_sim);

  static constexpr int kRoot = 0;
  // The trace id of the root.
  static constexpr int kRootTrace = -1;
  int NumNodes() const { return static_cast<int>(parents_.size()); }
  int strands(int node) const { return strands_[node]; }
  // The id of the trace that recorded `node` (kRootTrace for the root; a
  // node splitting an edge belongs to the edge's child's trace).
  int TraceOf(int node) const { return traces_of_[node]; }
  // Every edge, as its child node, in the order the edges were made: a
  // split adds only its upper part (the lower part lies within the edge
  // that was split). For indexing the traces as they grow.
  const std::vector<int32_t>& EdgesInOrder() const { return edges_in_order_; }

  // Starts trace `trace` (>= 0) with a tip node carrying one strand.
  TraceCursor StartTrace(const Eigen::Vector3d& position_in_sim, int trace);

  // Whether a particle that moved from `from` to `to` leaves its run: `to`
  // lies farther than `tolerance` from the run's line, or moved backwards
  // along it; always once the run has started if `tolerance` is 0. Then
  // `from` must be recorded (RecordNode). Pure; thread-safe.
  static bool LeavesRun(const TraceCursor& cursor, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to, double tolerance);
  // Starts a new run at the cursor's last node through `to` if it has none.
  static void StartRunIfNeeded(TraceCursor* cursor, const Eigen::Vector3d& to);

  // Appends a node at `position_in_sim` carrying `mass` strands after the
  // cursor's last node, and moves the cursor there (the run restarts).
  int RecordNode(TraceCursor* cursor, const Eigen::Vector3d& position_in_sim, int mass);
  // A node of this particle at its current position: the last node if the
  // particle has not moved since (and it is not the seeding tip), else a new
  // one. Used where traces join (merges, the base).
  int NodeAtPosition(TraceCursor* cursor, const Eigen::Vector3d& position_in_sim, int mass);

  // Ends a trace: its last node's parent becomes `parent` (a survivor's node,
  // a node of a finished trace, or the root), and `parent` and every node
  // downstream of it to the end of its trace gain `mass` strands.
  void EndTrace(const TraceCursor& cursor, int parent, int mass);

  // Splits the edge from `child` to its parent at `point_in_sim` with a new
  // node (carrying the edge's strands), which it returns.
  int SplitEdge(int child, const Eigen::Vector3d& point_in_sim);

  // Calls visit(child) for every edge (child -> parent) upstream of `node`,
  // i.e. of its subtree, and for `node`'s own edge if it has a parent.
  template <typename Visit>
  void ForEachEdgeUpstream(int node, const Visit& visit) const;

  Eigen::Vector3d Position(int node) const { return positions_[node].cast<double>(); }
  int Parent(int node) const { return parents_[node]; }
  bool IsTip(int node) const { return first_child_[node] < 0; }

  // The traces as a skeleton in world units (the root exactly at
  // `root_in_world`), nodes listed breadth-first from the root. Chains
  // between junctions are simplified with Douglas-Peucker at
  // `simplify_tolerance` voxels (0 keeps every node). Throws Error if a node
  // was never linked.
  SkeletonGraph ToSkeleton(const SimFrame& frame, const Eigen::Vector3d& root_in_world,
                           double simplify_tolerance) const;

 private:
  int AddNode(const Eigen::Vector3d& position_in_sim, int strands, int trace);
  // Links `node` below `parent`; a new edge is listed in EdgesInOrder.
  void SetParent(int node, int parent, bool new_edge = true);
  // Marks the nodes Douglas-Peucker keeps on every chain between key nodes
  // (the root, junctions, tips), which are always kept.
  std::vector<char> KeptNodes(double tolerance) const;

  std::vector<Eigen::Vector3f> positions_;  // sim frame
  std::vector<int32_t> parents_;            // -1: the root, or not linked yet
  std::vector<int32_t> strands_;
  std::vector<int32_t> traces_of_;
  std::vector<int32_t> edges_in_order_;
  // Children as singly linked lists (-1 ends a list).
  std::vector<int32_t> first_child_;
  std::vector<int32_t> next_sibling_;
};

template <typename Visit>
void TraceGraph::ForEachEdgeUpstream(int node, const Visit& visit) const {
  if (parents_[node] >= 0) visit(node);
  std::vector<int> stack;
  for (int child = first_child_[node]; child >= 0; child = next_sibling_[child]) {
    stack.push_back(child);
  }
  while (!stack.empty()) {
    const int current = stack.back();
    stack.pop_back();
    visit(current);
    for (int child = first_child_[current]; child >= 0; child = next_sibling_[child]) {
      stack.push_back(child);
    }
  }
}

}  // namespace sylva

#endif  // SYLVA_SIMULATE_TRACE_GRAPH_H_
