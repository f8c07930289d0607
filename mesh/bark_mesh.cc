#include "mesh/bark_mesh.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "core/util/check.h"

namespace sylva {
namespace {

// Pushing a joint's cuts out: factor per try, number of tries.
constexpr double kPushFactor = 1.25;
constexpr int kMaxPushes = 8;
// A ring must lie behind every other ring's plane by this fraction of the
// joint's largest ring radius.
constexpr double kFaceClearance = 1e-3;
// Tie-breaking jitter of the hull's points, as a fraction of the joint's size.
constexpr double kJitter = 1e-7;

// Where a joint cuts one of its exits: the edge from `node` (in the joint)
// to `outside`, cut at distance `t` from `node`.
struct Exit {
  int node = -1;
  int outside = -1;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, node -> outside
  double length = 0.0;                                  // of the edge
  double radius = 0.0;                                  // of the cut ring
  double t = 0.0;
  Eigen::Vector3d Center(const SkeletonGraph& skeleton) const {
    return skeleton.nodes[node].position + t * direction;
  }
};

// Eq. 5.25: the radius of the smallest sphere around the junction on which
// circles of radii r1, r2 perpendicular to two exits at angle gamma meet.
double EnclosingSphereRadius(double r1, double r2, double gamma) {
  if (gamma <= 1e-9) return std::numeric_limits<double>::infinity();
  const double alpha = std::atan2(std::sin(gamma), r2 / r1 + std::cos(gamma));
  // alpha >= 90 degrees: the circles cannot meet on a sphere that holds both
  // (wide angles); the smallest such sphere is the thicker exit's radius.
  if (alpha >= M_PI / 2) return std::max(r1, r2);
  return std::max(r1 / std::sin(alpha), std::max(r1, r2));
}

class WatertightMesher {
 public:
  WatertightMesher(const SkeletonGraph& skeleton, const BarkMeshOptions& options,
                   BarkMeshSummary* summary)
      : skeleton_(skeleton), options_(options), summary_(summary) {
    children_ = skeleton.Children();
    for (const SkeletonNode& node : skeleton.nodes) max_radius_ = std::max(max_radius_, node.radius);
    group_.assign(skeleton.NumNodes(), -1);
  }

  TriangleMesh Run() {
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (children_[i].size() >= 2) {
        group_[i] = i;
        ++summary_->junctions;
      }
    }
    FormJoints();
    TriangleMesh mesh;
    material_ = mesh.AddMaterial(options_.tube.bark);
    MeshPieces(&mesh);
    for (auto& [root, rings] : joint_rings_) {
      ++summary_->joints;
      (void)root;
      if (rings.size() >= 2 && !BuildHull(rings, &mesh)) ++summary_->failed_joints;
    }
    return mesh;
  }

 private:
  double RingRadius(double r) const {
    return std::max(r, options_.min_radius_fraction * max_radius_);
  }

  int Group(int node) const {
    if (group_[node] < 0) return -1;
    int g = node;
    while (group_[g] != g) g = group_[g];
    return g;
  }
  void Join(int a, int b) {  // b (a node, maybe in a group) joins a's group
    const int ga = Group(a);
    const int gb = Group(b);
    if (gb < 0) {
      group_[b] = ga;
    } else if (gb != ga) {
      group_[gb] = ga;
    }
  }

  // The edges leaving group g, with cuts from eq. 5.25 (not yet checked).
  std::vector<Exit> ExitsOf(int g, const std::vector<int>& members) const {
    std::vector<Exit> exits;
    for (int u : members) {
      std::vector<int> neighbours = children_[u];
      const int parent = skeleton_.nodes[u].parent_idx;
      if (parent >= 0) neighbours.insert(neighbours.begin(), parent);
      for (int v : neighbours) {
        if (Group(v) == g) continue;
        Exit e;
        e.node = u;
        e.outside = v;
        const Eigen::Vector3d d = skeleton_.nodes[v].position - skeleton_.nodes[u].position;
        e.length = d.norm();
        e.direction = e.length > 0 ? Eigen::Vector3d(d / e.length) : Eigen::Vector3d::Zero();
        e.radius = RingRadius(v == parent ? skeleton_.nodes[u].radius : skeleton_.nodes[v].radius);
        exits.push_back(e);
      }
    }
    double rho = 0.0;
    for (const Exit& e : exits) rho = std::max(rho, e.radius);
    for (size_t i = 0; i < exits.size(); ++i) {
      for (size_t j = i + 1; j < exits.size(); ++j) {
        const double gamma =
            std::acos(std::clamp(exits[i].direction.dot(exits[j].direction), -1.0, 1.0));
        rho = std::max(rho, EnclosingSphereRadius(exits[i].radius, exits[j].radius, gamma));
      }
    }
    rho *= 1 + options_.sphere_margin;
    for (Exit& e : exits) e.t = std::sqrt(std::max(0.0, rho * rho - e.radius * e.radius));
    return exits;
  }

  // Is every cut ring strictly behind every other ring's plane?
  bool RingsAreHullFaces(const std::vector<Exit>& exits) const {
    double largest = 0.0;
    for (const Exit& e : exits) largest = std::max(largest, e.radius);
    for (size_t i = 0; i < exits.size(); ++i) {
      const Eigen::Vector3d ci = exits[i].Center(skeleton_);
      for (size_t j = 0; j < exits.size(); ++j) {
        if (i == j) continue;
        const double c = exits[i].direction.dot(exits[j].direction);
        const double reach = (exits[j].Center(skeleton_) - ci).dot(exits[i].direction) +
                             exits[j].radius * std::sqrt(std::max(0.0, 1 - c * c));
        if (reach > -kFaceClearance * largest) return false;
      }
    }
    return true;
  }

  // Groups junctions into joints whose cuts fit; fills exits_.
  void FormJoints() {
    bool changed = true;
    while (changed) {
      changed = false;
      exits_.clear();
      exit_count_.clear();
      push_count_.clear();
      std::map<int, std::vector<int>> groups;
      for (int i = 0; i < skeleton_.NumNodes(); ++i) {
        if (group_[i] >= 0) groups[Group(i)].push_back(i);
      }
      for (auto& [g, members] : groups) {
        std::vector<Exit> exits = ExitsOf(g, members);
        int pushes = 0;
        while (exits.size() >= 2 && !RingsAreHullFaces(exits) && pushes < kMaxPushes) {
          for (Exit& e : exits) e.t *= kPushFactor;
          ++pushes;
        }
        // The exit that fits worst on its edge.
        int worst = -1;
        double worst_ratio = 0.0;
        for (size_t k = 0; k < exits.size(); ++k) {
          const double ratio = exits[k].length > 0 ? exits[k].t / exits[k].length : 1e300;
          if (ratio > worst_ratio) {
            worst_ratio = ratio;
            worst = static_cast<int>(k);
          }
        }
        const bool faces = exits.size() < 2 || RingsAreHullFaces(exits);
        if (getenv("BARK_DEBUG")) { fprintf(stderr, "group %d exits %zu pushes %d worst %g faces %d\n", g, exits.size(), pushes, worst_ratio, faces); for (auto& e : exits) fprintf(stderr, "  %d->%d t %g L %g r %g dir %g %g %g\n", e.node, e.outside, e.t, e.length, e.radius, e.direction.x(), e.direction.y(), e.direction.z()); }
        if (worst >= 0 && (worst_ratio > options_.max_cut_fraction || !faces)) {
          Join(g, exits[worst].outside);
          ++summary_->fallbacks;
          changed = true;
          break;
        }
        if (pushes > 0) push_count_[g] = pushes;
        exit_count_[g] = static_cast<int>(exits.size());
        for (const Exit& e : exits) exits_[{e.node, e.outside}] = e;
      }
      if (changed) continue;
      // Edges cut by two joints: both cuts must fit together.
      for (const auto& [key, e] : exits_) {
        const auto other = exits_.find({key.second, key.first});
        if (other == exits_.end()) continue;
        if (e.t + other->second.t > options_.max_cut_fraction * e.length) {
          Join(key.first, key.second);
          ++summary_->fallbacks;
          changed = true;
          break;
        }
      }
    }
    std::set<int> groups;
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (group_[i] < 0) continue;
      groups.insert(Group(i));
      if (children_[i].empty()) ++summary_->swallowed_tips;
    }
    for (int g : groups) {
      int members = 0;
      for (int i = 0; i < skeleton_.NumNodes(); ++i) members += Group(i) == g ? 1 : 0;
      if (members == 1) ++summary_->bridged;
    }
    summary_->pushed_out = static_cast<int>(push_count_.size());
  }

  // Every chain between joints, tips and the root becomes one open or capped tube.
  void MeshPieces(TriangleMesh* mesh) {
    const int root = skeleton_.RootIdx();
    std::vector<int> starts;
    for (int u = 0; u < skeleton_.NumNodes(); ++u) {
      if (group_[u] >= 0 || u == root) starts.push_back(u);
    }
    for (int u : starts) {
      for (int v : children_[u]) {
        if (group_[u] >= 0 && Group(v) == Group(u)) continue;  // inside a joint
        std::vector<int> chain = {u, v};
        while (group_[chain.back()] < 0 && children_[chain.back()].size() == 1) {
          chain.push_back(children_[chain.back()][0]);
        }
        MeshPiece(chain, mesh);
      }
    }
  }

  void MeshPiece(const std::vector<int>& chain, TriangleMesh* mesh) {
    const int u = chain.front(), w = chain.back();
    // A joint left with a single exit is no joint: that tube gets a cap.
    const bool start_cut = group_[u] >= 0 && exit_count_[Group(u)] >= 2;
    const bool end_cut = group_[w] >= 0 && exit_count_[Group(w)] >= 2;
    BranchTube tube;
    auto add = [&](const Eigen::Vector3d& p, double r, bool force) {
      if (!force && !tube.control_points.empty() &&
          (p - tube.control_points.back()).norm() <= 1e-9 * (1 + p.norm())) {
        return;
      }
      tube.control_points.push_back(p);
      tube.radii.push_back(RingRadius(r));
    };
    const Exit* start = start_cut ? &exits_.at({u, chain[1]}) : nullptr;
    const Exit* end = end_cut ? &exits_.at({w, chain[chain.size() - 2]}) : nullptr;
    if (start != nullptr) {
      add(start->Center(skeleton_), start->radius, true);
    } else {
      add(skeleton_.nodes[u].position, skeleton_.nodes[u].radius, true);
    }
    for (size_t k = 1; k + 1 < chain.size(); ++k) {
      add(skeleton_.nodes[chain[k]].position, skeleton_.nodes[chain[k]].radius, false);
    }
    const Eigen::Vector3d last =
        end != nullptr ? end->Center(skeleton_) : skeleton_.nodes[w].position;
    if (!tube.control_points.empty() && tube.control_points.size() > 1 &&
        (last - tube.control_points.back()).norm() <= 1e-9 * (1 + last.norm())) {
      tube.control_points.pop_back();
      tube.radii.pop_back();
    }
    add(last, end != nullptr ? end->radius : skeleton_.nodes[w].radius, true);
    if (start != nullptr) tube.radii.front() = start->radius;
    if (end != nullptr) tube.radii.back() = end->radius;
    for (size_t k = 0; k + 1 < tube.control_points.size(); ++k) {
      tube.rings_per_segment.push_back(TubeRingsPerSegment(
          (tube.control_points[k + 1] - tube.control_points[k]).norm(), options_.tube));
    }
    tube.sides = TubeSides(*std::max_element(tube.radii.begin(), tube.radii.end()), max_radius_,
                           options_.tube);
    const int first = mesh->NumVertices();
    AppendTube(SampleTubeRings(tube), tube.sides, material_, mesh, !start_cut, !end_cut);
    ++summary_->pieces;
    const int rings = tube.NumRings();
    // Ring edges the joint must use: the reverse of the tube's.
    if (start_cut) {
      JointRing ring;
      for (int j = 0; j < tube.sides; ++j) ring.vertices.push_back(first + j);
      ring.reversed = true;  // the tube uses j -> j+1; the joint j+1 -> j
      joint_rings_[Group(u)].push_back(ring);
    }
    if (end_cut) {
      JointRing ring;
      for (int j = 0; j < tube.sides; ++j) ring.vertices.push_back(first + (rings - 1) * tube.sides + j);
      ring.reversed = false;  // the tube uses j+1 -> j; the joint j -> j+1
      joint_rings_[Group(w)].push_back(ring);
    }
  }

  struct JointRing {
    std::vector<int> vertices;  // mesh indices in ring order
    bool reversed = false;      // the joint uses vertices[j+1] -> vertices[j]
  };

  // The convex hull of the rings' vertices without the ring polygons, by
  // gift wrapping from the ring edges. False if it did not close cleanly.
  bool BuildHull(const std::vector<JointRing>& rings, TriangleMesh* mesh) {
    std::vector<int> ids, ring_of;
    for (size_t r = 0; r < rings.size(); ++r) {
      for (int v : rings[r].vertices) {
        ids.push_back(v);
        ring_of.push_back(static_cast<int>(r));
      }
    }
    const int n = static_cast<int>(ids.size());
    std::map<int, int> local;
    for (int i = 0; i < n; ++i) local[ids[i]] = i;
    Eigen::AlignedBox3d box;
    for (int v : ids) box.extend(mesh->vertices[v].cast<double>());
    const double size = box.sizes().maxCoeff();
    std::vector<Eigen::Vector3d> p(n);
    uint64_t state = 0x9e3779b97f4a7c15ULL;
    auto next = [&state]() {  // splitmix64 in [-1, 1)
      state += 0x9e3779b97f4a7c15ULL;
      uint64_t z = state;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      z ^= z >> 31;
      return static_cast<double>(z >> 11) / static_cast<double>(1ULL << 52) - 1.0;
    };
    for (int i = 0; i < n; ++i) {
      p[i] = mesh->vertices[ids[i]].cast<double>() +
             kJitter * size * Eigen::Vector3d(next(), next(), next());
    }
    std::set<std::pair<int, int>> used;
    std::vector<std::pair<int, int>> needs;
    for (const JointRing& ring : rings) {
      const int s = static_cast<int>(ring.vertices.size());
      for (int j = 0; j < s; ++j) {
        const int a = local[ring.vertices[j]], b = local[ring.vertices[(j + 1) % s]];
        if (ring.reversed) {
          used.insert({a, b});
          needs.push_back({b, a});
        } else {
          used.insert({b, a});
          needs.push_back({a, b});
        }
      }
    }
    std::vector<Eigen::Vector3i> triangles;
    const size_t max_triangles = 4 * static_cast<size_t>(n) + 8;
    while (!needs.empty()) {
      const auto [a, b] = needs.back();
      needs.pop_back();
      if (used.count({a, b})) continue;
      if (triangles.size() > max_triangles) return false;
      const bool same_ring = ring_of[a] == ring_of[b];
      int best = -1;
      for (int q = 0; q < n; ++q) {
        if (q == a || q == b || (same_ring && ring_of[q] == ring_of[a])) continue;
        if (best < 0 || (p[b] - p[a]).cross(p[best] - p[a]).dot(p[q] - p[a]) > 0) best = q;
      }
      if (best < 0) return false;
      const int c = best;
      if (used.count({b, c}) || used.count({c, a})) return false;
      used.insert({a, b});
      used.insert({b, c});
      used.insert({c, a});
      triangles.emplace_back(a, b, c);
      if (!used.count({c, b})) needs.push_back({c, b});
      if (!used.count({a, c})) needs.push_back({a, c});
    }
    for (const Eigen::Vector3i& t : triangles) {
      mesh->AddTriangle(ids[t[0]], ids[t[1]], ids[t[2]], material_);
    }
    return true;
  }

  const SkeletonGraph& skeleton_;
  const BarkMeshOptions& options_;
  BarkMeshSummary* summary_;
  std::vector<std::vector<int>> children_;
  double max_radius_ = 0.0;
  std::vector<int> group_;  // union-find parent of joint nodes, -1 elsewhere
  std::map<std::pair<int, int>, Exit> exits_;
  std::map<int, int> push_count_;
  std::map<int, int> exit_count_;
  std::map<int, std::vector<JointRing>> joint_rings_;
  int material_ = 0;
};

}  // namespace

void BarkMeshOptions::Check() const {
  tube.Check();
  SYLVA_CHECK_INPUT(sphere_margin > 0 && sphere_margin <= 10, "BarkMesh.sphere_margin")
      << "must be in (0, 10], got " << sphere_margin;
  SYLVA_CHECK_INPUT(max_cut_fraction > 0 && max_cut_fraction < 1, "BarkMesh.max_cut_fraction")
      << "must be in (0, 1), got " << max_cut_fraction;
  SYLVA_CHECK_INPUT(min_radius_fraction > 0 && min_radius_fraction < 1,
                    "BarkMesh.min_radius_fraction")
      << "must be in (0, 1), got " << min_radius_fraction;
}

std::string BarkMeshSummary::BriefReport() const {
  std::ostringstream out;
  out << "Watertight bark: " << junctions << " junctions in " << joints << " joints (" << bridged
      << " single-junction, " << fallbacks << " fallback merges, " << pushed_out
      << " pushed out, " << swallowed_tips << " tips swallowed";
  if (failed_joints > 0) out << ", " << failed_joints << " FAILED";
  out << "), " << pieces << " tubes, " << triangles << " triangles in " << seconds
      << " s; radii: " << radius_source << ".";
  return out.str();
}

TriangleMesh MeshBarkWatertight(const SkeletonGraph& skeleton, const BarkMeshOptions& options,
                                BarkMeshSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  BarkMeshSummary local;
  if (summary == nullptr) summary = &local;
  *summary = BarkMeshSummary();
  summary->radius_source = skeleton.radius_source;
  options.Check();
  // Validates the skeleton exactly as MeshBranches does.
  PlanBranchTubes(skeleton, options.tube);
  TriangleMesh mesh;
  if (skeleton.NumNodes() >= 2) mesh = WatertightMesher(skeleton, options, summary).Run();
  summary->triangles = mesh.NumTriangles();
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mesh;
}

}  // namespace sylva
