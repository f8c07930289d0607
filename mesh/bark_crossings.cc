#include "mesh/bark_crossings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "mesh/mesh_checks.h"

namespace sylva {
namespace {

// Edges at most this many apart in the tree (the same edge: 0, sharing a
// node: 1) whose path passes a junction are that junction's pieces: its
// exits and the edges next to them, which a joint's hull or an attachment
// spans.
constexpr int kJunctionHops = 3;
// The skeleton capsules of two edges overlap if their segments come closer
// than this factor times the sum of their radii: a 5 % margin of this
// diagnostic, because tubes that nearly touch already cross once their
// rings are polygons (with circle_area their vertices reach beyond the
// radius).
constexpr double kCapsuleInflation = 1.05;

// Tells whose a crossing pair of bark triangles is. Edges are named by
// their child node.
class CrossingClassifier {
 public:
  CrossingClassifier(const SkeletonGraph& skeleton, const TriangleMesh& bark,
                     const std::vector<BarkTriangleOrigin>& origins)
      : nodes_(skeleton.nodes), bark_(bark), origins_(origins), children_(skeleton.Children()) {
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      if (nodes_[i].parent_idx >= 0) edges_.push_back(i);
    }
    // The child continuing each node's branch axis.
    axis_child_.assign(skeleton.NumNodes(), -1);
    for (const BranchAxis& axis : skeleton.BranchAxes()) {
      for (size_t k = 1; k + 1 < axis.size(); ++k) axis_child_[axis[k]] = axis[k + 1];
      if (axis.size() >= 2 && axis_child_[axis[0]] < 0) axis_child_[axis[0]] = axis[1];
    }
  }

  // Counts the pair of triangles t1, t2 in `result`.
  void Count(int t1, int t2, BarkCrossings* result) const {
    const int e1 = NearestEdge(t1), e2 = NearestEdge(t2);
    if (e1 < 0 || e2 < 0) {
      ++result->other;
      return;
    }
    const int hops = e1 == e2 ? 0 : Hops(e1, e2);
    if (hops == 0 || (hops <= kJunctionHops && !JunctionBetween(e1, e2))) {
      ++result->within_branch;
    } else if (hops <= kJunctionHops) {
      ++result->at_junctions;
    } else {
      ++(CapsulesCollide(e1, e2) ? result->colliding_branches : result->other);
    }
  }

 private:
  // The edge triangle t was made for (see the header).
  int NearestEdge(int t) const {
    const BarkTriangleOrigin& o = origins_[t];
    if (o.kind == BarkTriangleOrigin::kAttachment) return o.next;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += bark_.vertices[bark_.triangles[t][k]].cast<double>() / 3.0;
    Nearest nearest;
    if (o.kind == BarkTriangleOrigin::kTube && o.next >= 0) {
      // Along the tube's axis, down the axis children or up the parents.
      if (nodes_[o.next].parent_idx == o.node) {
        for (int e = o.next; e >= 0; e = axis_child_[e]) Consider(c, e, &nearest);
      } else {
        for (int e = o.node; nodes_[e].parent_idx >= 0; e = nodes_[e].parent_idx) {
          Consider(c, e, &nearest);
        }
      }
      return nearest.edge;
    }
    for (int e : edges_) Consider(c, e, &nearest);
    return nearest.edge;
  }

  struct Nearest {
    int edge = -1;
    double gap = std::numeric_limits<double>::infinity();
  };
  // Keeps edge e in `nearest` if its surface is nearer point c.
  void Consider(const Eigen::Vector3d& c, int e, Nearest* nearest) const {
    const SkeletonNode& parent = nodes_[nodes_[e].parent_idx];
    double s = 0.0;
    const double d = std::sqrt(SegmentDistance2(c, parent.position, nodes_[e].position, &s));
    const double gap = std::abs(d - ((1 - s) * parent.radius + s * nodes_[e].radius));
    if (gap < nearest->gap) {
      nearest->gap = gap;
      nearest->edge = e;
    }
  }

  // Edges between edge a and edge b: 0 the same, 1 sharing a node, ...
  int Hops(int a, int b) const {
    std::map<int, int> up;
    int k = 0;
    for (int x = a; x >= 0; x = nodes_[x].parent_idx) up[x] = k++;
    int steps = 0;
    for (int x = b; x >= 0; x = nodes_[x].parent_idx, ++steps) {
      const auto it = up.find(x);
      if (it != up.end()) return it->second + steps;
    }
    return std::numeric_limits<int>::max();
  }

  // The tree path between nodes x and y (both included).
  std::vector<int> Path(int x, int y) const {
    std::vector<int> up_x, up_y;
    std::set<int> on_x;
    for (int n = x; n >= 0; n = nodes_[n].parent_idx) {
      up_x.push_back(n);
      on_x.insert(n);
    }
    int meet = y;
    for (; meet >= 0 && !on_x.count(meet); meet = nodes_[meet].parent_idx) up_y.push_back(meet);
    std::vector<int> path;
    for (int n : up_x) {
      path.push_back(n);
      if (n == meet) break;
    }
    path.insert(path.end(), up_y.rbegin(), up_y.rend());
    return path;
  }

  // Do edges a and b meet through a node of 2+ children (a junction), on
  // the shortest path between their end nodes?
  bool JunctionBetween(int a, int b) const {
    std::vector<int> shortest;
    for (int x : {a, nodes_[a].parent_idx}) {
      for (int y : {b, nodes_[b].parent_idx}) {
        std::vector<int> path = Path(x, y);
        if (shortest.empty() || path.size() < shortest.size()) shortest = std::move(path);
      }
    }
    for (int n : shortest) {
      if (children_[n].size() >= 2) return true;
    }
    return false;
  }

  // The edge and the edges sharing a node with it.
  std::set<int> Around(int e) const {
    std::set<int> near = {e};
    const int p = nodes_[e].parent_idx;
    if (nodes_[p].parent_idx >= 0) near.insert(p);
    for (int c : children_[p]) near.insert(c);
    for (int c : children_[e]) near.insert(c);
    return near;
  }

  // Whether the capsules of edge a and b, or of edges sharing a node with
  // them, overlap (kCapsuleInflation).
  bool CapsulesCollide(int e1, int e2) const {
    bool collide = false;
    for (int a : Around(e1)) {
      for (int b : Around(e2)) collide = collide || CapsulesOverlap(a, b);
    }
    return collide;
  }
  bool CapsulesOverlap(int a, int b) const {
    const SkeletonNode& pa = nodes_[nodes_[a].parent_idx];
    const SkeletonNode& pb = nodes_[nodes_[b].parent_idx];
    const double reach = kCapsuleInflation * (std::max(nodes_[a].radius, pa.radius) +
                                              std::max(nodes_[b].radius, pb.radius));
    return SegmentSegmentDistance2(pa.position, nodes_[a].position, pb.position,
                                   nodes_[b].position) < reach * reach;
  }

  const std::vector<SkeletonNode>& nodes_;
  const TriangleMesh& bark_;
  const std::vector<BarkTriangleOrigin>& origins_;
  const std::vector<std::vector<int>> children_;
  std::vector<int> edges_;       // every node with a parent
  std::vector<int> axis_child_;  // the child continuing each node's branch axis, else -1
};

}  // namespace

std::string BarkCrossings::BriefReport() const {
  std::ostringstream out;
  out << pairs << " crossing triangle pairs: " << at_junctions << " at junctions, " << within_branch
      << " within a branch, " << colliding_branches
      << " where skeleton branches pass through each other, " << other << " other";
  return out.str();
}

BarkCrossings ClassifyBarkCrossings(const SkeletonGraph& skeleton, const TriangleMesh& bark,
                                    const std::vector<BarkTriangleOrigin>& origins) {
  SYLVA_CHECK(static_cast<int>(origins.size()) == bark.NumTriangles());
  const std::vector<std::pair<int, int>> pairs = FindSelfIntersections(bark);
  const CrossingClassifier classifier(skeleton, bark, origins);
  BarkCrossings result;
  result.pairs = static_cast<int64_t>(pairs.size());
  for (const auto& [t1, t2] : pairs) classifier.Count(t1, t2, &result);
  return result;
}

}  // namespace sylva
