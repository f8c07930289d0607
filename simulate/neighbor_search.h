// Exact nearest-neighbour search among a set of points that is rebuilt every
// step of the particle flow (the particles move), behind one small interface
// with three implementations:
//   - "uniform_grid": a dense uniform grid over the points' bounds with about one
//                    cell per point, built by a counting sort (O(N)); queries
//                    visit rings of cells outwards until no closer point can
//                    exist. The default: the fastest measured (see
//                    tests/bench/particle_flow_benchmark.cc).
//   - "embree":      Embree 3 point queries (rtcPointQuery) on a BVH of
//                    user-geometry points, rebuilt per step at low build
//                    quality; the query radius shrinks as closer points are
//                    found.
//   - "brute_force": every pair, O(N) per query; the reference for tests and
//                    benchmarks.
// All three return the same answer: the nearest point within a maximum
// distance, ties broken towards the lowest index, distances compared in
// double precision.
#ifndef SYLVA_SIMULATE_NEIGHBOR_SEARCH_H_
#define SYLVA_SIMULATE_NEIGHBOR_SEARCH_H_

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace sylva {

enum class NeighborSearchKind { kUniformGrid, kEmbree, kBruteForce };

// "uniform_grid", "embree" or "brute_force"; throws InputError naming `source`
// (the option) for anything else.
NeighborSearchKind NeighborSearchKindFromName(const std::string& name, const std::string& source);
const char* NeighborSearchName(NeighborSearchKind kind);

class NeighborSearch {
 public:
  virtual ~NeighborSearch() = default;

  // Indexes `points` (any consistent units). The vector is referenced, not
  // copied: it must stay alive and unchanged until the next Build().
  virtual void Build(const std::vector<Eigen::Vector3d>& points) = 0;

  // Index of the indexed point nearest to `query`, other than `exclude_idx`
  // (-1 excludes none), at a distance < `max_distance` (may be +infinity);
  // -1 if there is none. `*distance` receives its distance. Ties go to the
  // lowest index. Const and thread-safe between Build() calls.
  virtual int Nearest(const Eigen::Vector3d& query, int exclude_idx, double max_distance,
                      double* distance) const = 0;

  // The nearest other point to indexed point `idx`.
  int NearestOther(int idx, double max_distance, double* distance) const;

  // NearestOther for every indexed point, in parallel (TBB): (*nearest)[i]
  // and (*distances)[i] for point i. Implementations may visit the points
  // in a cache-friendly order; the results are the same.
  virtual void AllNearestOthers(double max_distance, std::vector<int>* nearest,
                                std::vector<double>* distances) const;

 protected:
  const std::vector<Eigen::Vector3d>* points_ = nullptr;
};

std::unique_ptr<NeighborSearch> MakeNeighborSearch(NeighborSearchKind kind);

}  // namespace sylva

#endif  // SYLVA_SIMULATE_NEIGHBOR_SEARCH_H_
