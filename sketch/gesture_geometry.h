// The geometry a gesture tree grows with (sketch/gesture_tree.h; Murakami
// et al. 4.1.3, 4.1.5): the turtle's frame and its turns, the capsules of
// branch segments in a uniform hash grid for the collision tests, and path
// lengths along the growing skeleton, which tell capsules of one tube
// (adjacent) from colliding ones. Internal to sketch/gesture_*.cc.
#ifndef SYLVA_SKETCH_GESTURE_GEOMETRY_H_
#define SYLVA_SKETCH_GESTURE_GEOMETRY_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace sylva {
namespace gesture_internal {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegree = kPi / 180.0;
// Below this fraction of the two radii the closest points of two axes give
// no bypass direction (4.1.5: "if the distance is equal to or smaller than
// a threshold"), and the half-space with fewer segments is taken.
inline constexpr double kBypassThreshold = 0.25;
// Two capsules are one tube (adjacent) when the skeleton path between
// their nearest ends is at most this many times the sum of their radii:
// a branch leaving at 30 degrees or more clears its parent's tube there.
inline constexpr double kAdjacentReach = 2.0;

// --- turtle frame -------------------------------------------------------

// Heading, left, up; right-handed (H x L = U).
struct Frame {
  Eigen::Vector3d h = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d l = Eigen::Vector3d::UnitX();
  Eigen::Vector3d u = Eigen::Vector3d::UnitY();
};

// Rotates a and b about axis by angle (right hand).
inline void Rotate(const Eigen::Vector3d& axis, double degrees, Eigen::Vector3d* a,
                   Eigen::Vector3d* b) {
  const double c = std::cos(degrees * kDegree), s = std::sin(degrees * kDegree);
  const Eigen::Vector3d a0 = *a, b0 = *b;
  *a = a0 * c + axis.cross(a0) * s;
  *b = b0 * c + axis.cross(b0) * s;
}

inline void Yaw(double deg, Frame* f) { Rotate(f->u, deg, &f->h, &f->l); }    // + (turn left)
inline void Pitch(double deg, Frame* f) { Rotate(f->l, deg, &f->h, &f->u); }  // & (pitch down)
inline void Roll(double deg, Frame* f) { Rotate(f->h, deg, &f->l, &f->u); }   // / (roll)

// The turn to heading `d` as a yaw about U then a pitch about the new L
// (4.1.3: the axes in the order U, L, H; no roll needed for a direction).
inline std::pair<double, double> TurnTo(const Frame& frame, const Eigen::Vector3d& d) {
  const double yaw = std::atan2(d.dot(frame.l), d.dot(frame.h)) / kDegree;
  Frame turned = frame;
  Yaw(yaw, &turned);
  const double pitch = std::atan2(-d.dot(turned.u), d.dot(turned.h)) / kDegree;
  return {yaw, pitch};
}

// --- capsules -------------------------------------------------------------

// Skeleton nodes with their path length from the root, for the adjacency
// of capsules (path between their nearest ends <= sum of radii).
class TreePaths {
 public:
  void Add(int parent, double length) {
    parent_.push_back(parent);
    hops_.push_back(parent < 0 ? 0 : hops_[parent] + 1);
    dist_.push_back(parent < 0 ? 0.0 : dist_[parent] + length);
  }
  double Between(int u, int v) const {
    const double du = dist_[u], dv = dist_[v];
    while (hops_[u] > hops_[v]) u = parent_[u];
    while (hops_[v] > hops_[u]) v = parent_[v];
    while (u != v) u = parent_[u], v = parent_[v];
    return du + dv - 2 * dist_[u];
  }
  // Path between the nearest ends of edges (a0, a1) and (b0, b1).
  double BetweenEdges(int a0, int a1, int b0, int b1) const {
    return std::min(std::min(Between(a0, b0), Between(a0, b1)),
                    std::min(Between(a1, b0), Between(a1, b1)));
  }

 private:
  std::vector<int> parent_, hops_;
  std::vector<double> dist_;
};

struct Capsule {
  Eigen::Vector3d a, b;
  double radius;
  int node_a, node_b;  // skeleton nodes (parent, child)
  int module;          // the module that drew it (-1: none)
};

// Capsules in a uniform hash grid.
class CapsuleGrid {
 public:
  explicit CapsuleGrid(double cell) : cell_(cell) {}
  const std::vector<Capsule>& capsules() const { return capsules_; }
  void Add(const Capsule& c) {
    const int index = static_cast<int>(capsules_.size());
    capsules_.push_back(c);
    ForCells(c, [&](int64_t key) { cells_[key].push_back(index); });
  }
  // Calls visit(index) once per capsule whose cell range meets `c`'s.
  template <typename Visit>
  void Near(const Capsule& c, Visit visit) const {
    ++stamp_;
    seen_.resize(capsules_.size(), 0);
    ForCells(c, [&](int64_t key) {
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (int index : it->second) {
        if (seen_[index] == stamp_) continue;
        seen_[index] = stamp_;
        visit(index);
      }
    });
  }

 private:
  template <typename Visit>
  void ForCells(const Capsule& c, Visit visit) const {
    const Eigen::Vector3d lo = c.a.cwiseMin(c.b).array() - c.radius;
    const Eigen::Vector3d hi = c.a.cwiseMax(c.b).array() + c.radius;
    const Eigen::Vector3i l = (lo / cell_).array().floor().cast<int>();
    const Eigen::Vector3i h = (hi / cell_).array().floor().cast<int>();
    for (int x = l.x(); x <= h.x(); ++x)
      for (int y = l.y(); y <= h.y(); ++y)
        for (int z = l.z(); z <= h.z(); ++z)
          visit((int64_t(x) * 73856093) ^ (int64_t(y) * 19349663) ^ (int64_t(z) * 83492791));
  }
  double cell_;
  std::vector<Capsule> capsules_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
  // Scratch of Near (not thread-safe).
  mutable std::vector<int> seen_;
  mutable int stamp_ = 0;
};

}  // namespace gesture_internal
}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_GEOMETRY_H_
