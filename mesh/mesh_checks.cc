#include "mesh/mesh_checks.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace sylva {
namespace {

// Relative tolerance of the intersection and degeneracy tests.
constexpr double kEpsilon = 1e-9;
// At most this many grid cells per triangle (larger ones go everywhere they touch anyway).
constexpr int64_t kMaxCellsPerAxis = 1 << 20;

// A box over more cells than this is taken to touch the grid (a superset
// is harmless where Touches is used).
constexpr int64_t kMaxCellsPerQuery = 64;
// Grids of at most this many cells get a bitmap of their occupied cells
// (16 MB) where many boxes are looked up.
constexpr uint64_t kMaxDenseCells = uint64_t{1} << 27;

using Tri = std::array<Eigen::Vector3d, 3>;

int Find(std::vector<int>* parent, int i) {
  while ((*parent)[i] != i) {
    (*parent)[i] = (*parent)[(*parent)[i]];
    i = (*parent)[i];
  }
  return i;
}

// A triangle's (unnormalised) normal and its length, computed once per
// triangle for all its pair tests.
struct TriPlane {
  Eigen::Vector3d n;
  double nn;
};

// Triangle t of `mesh` in double precision.
Tri TriangleOf(const TriangleMesh& mesh, int t) {
  const Eigen::Vector3i& f = mesh.triangles[t];
  return {mesh.vertices[f[0]].cast<double>(), mesh.vertices[f[1]].cast<double>(),
          mesh.vertices[f[2]].cast<double>()};
}

TriPlane PlaneOf(const Tri& t) {
  const Eigen::Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]);
  return {n, n.norm()};
}

// Does an edge of triangle `a` cross triangle t's interior (closed edges)?
// `eps` is an absolute tolerance on signed distances and barycentric
// margins. Each vertex's signed distance to t's plane is computed once and
// shared by its two edges.
bool EdgesCrossTriangle(const Tri& a, const Tri& t, const TriPlane& plane, double scale) {
  const Eigen::Vector3d& n = plane.n;
  const double nn = plane.nn;
  if (nn <= 0) return false;
  const double eps = kEpsilon * scale;
  double d[3];
  for (int k = 0; k < 3; ++k) d[k] = n.dot(a[k] - t[0]) / nn;
  for (int e = 0; e < 3; ++e) {
    const double dp = d[e], dq = d[(e + 1) % 3];
    if ((dp > -eps && dq > -eps) || (dp < eps && dq < eps)) continue;  // same side or coplanar
    const Eigen::Vector3d& p = a[e];
    const Eigen::Vector3d& q = a[(e + 1) % 3];
    const Eigen::Vector3d x = p + (dp / (dp - dq)) * (q - p);
    // x inside t with a margin: barycentric coordinates by sub-areas.
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      const Eigen::Vector3d& u = t[k];
      const Eigen::Vector3d& v = t[(k + 1) % 3];
      const double side = n.dot((v - u).cross(x - u)) / nn;  // > 0 inside
      inside = !(side <= eps * (v - u).norm());              // a NaN side does not reject
    }
    if (inside) return true;
  }
  return false;
}

bool TrianglesCross(const Tri& a, const TriPlane& plane_a, const Tri& b, const TriPlane& plane_b,
                    double scale) {
  return EdgesCrossTriangle(a, b, plane_b, scale) || EdgesCrossTriangle(b, a, plane_a, scale);
}

// Sorts `items` by key(item) (< 2^bits), stably: LSD radix passes of 16
// bits.
template <typename T, typename Key>
void RadixSort(std::vector<T>* items, int bits, const Key& key) {
  constexpr int kDigit = 16;
  constexpr uint64_t kMask = (uint64_t{1} << kDigit) - 1;
  std::vector<T> scratch(items->size());
  std::vector<size_t> count(kMask + 2);
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (const T& item : *items) ++count[((key(item) >> shift) & kMask) + 1];
    std::partial_sum(count.begin(), count.end(), count.begin());
    for (const T& item : *items) scratch[count[(key(item) >> shift) & kMask]++] = item;
    items->swap(scratch);
  }
}

// Bits needed to write values below `n` (n >= 1).
int BitsBelow(uint64_t n) {
  int bits = 0;
  while (bits < 64 && (n - 1) >> bits) ++bits;
  return bits;
}

// A grid cell's integer coordinates (each < 2^21) packed into one key.
uint64_t CellKey(int64_t x, int64_t y, int64_t z) {
  return static_cast<uint64_t>(x) | static_cast<uint64_t>(y) << 21 | static_cast<uint64_t>(z) << 42;
}

// The selected triangles bucketed in a uniform grid: sorted (cell, triangle)
// entries, each triangle's plane and box computed once.
struct TriangleGrid {
  std::vector<TriPlane> planes;
  std::vector<Eigen::AlignedBox3f> boxes;         // of the (float) vertices: exact
  std::vector<std::array<int32_t, 6>> ranges;     // cells: min x y z, max x y z
  std::vector<std::pair<uint64_t, int>> entries;  // (cell, triangle), sorted
  double scale = 1.0;  // the extent the tests' tolerances are relative to
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double cell = 1.0;
  std::array<int64_t, 3> last_cell = {0, 0, 0};
  std::vector<uint64_t> occupied;  // MarkOccupied's bitmap, if made

  // `scale` > 0: the tests' tolerances are relative to it, not to the
  // selected triangles' extent (a part of a mesh tested like the whole).
  TriangleGrid(const TriangleMesh& mesh, const std::vector<int>& selected, double given_scale = 0) {
    const int n = static_cast<int>(selected.size());
    planes.resize(n), boxes.resize(n), ranges.resize(n);
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096),
                      [&](const tbb::blocked_range<int>& part) {
                        for (int i = part.begin(); i < part.end(); ++i) {
                          const Eigen::Vector3i& f = mesh.triangles[selected[i]];
                          for (int k = 0; k < 3; ++k) boxes[i].extend(mesh.vertices[f[k]]);
                          planes[i] = PlaneOf(TriangleOf(mesh, selected[i]));
                        }
                      });
    Eigen::AlignedBox3d all;
    double extent_sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const Eigen::AlignedBox3d box = boxes[i].cast<double>();
      all.extend(box);
      extent_sum += box.sizes().maxCoeff();
    }
    scale = std::max(all.sizes().maxCoeff(), 1e-30);
    cell = std::max(2.0 * extent_sum / n, scale / kMaxCellsPerAxis);
    if (cell <= 0) cell = scale;
    if (given_scale > 0) scale = given_scale;
    origin = all.min();
    auto cell_of = [&](double v, int axis) {
      return std::clamp<int64_t>(static_cast<int64_t>(std::floor((v - all.min()[axis]) / cell)), 0,
                                 2 * kMaxCellsPerAxis - 1);
    };
    // Each triangle's cells, then its entries at its place in `entries`.
    std::vector<int64_t> first_entry(n + 1, 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096),
                      [&](const tbb::blocked_range<int>& part) {
                        for (int i = part.begin(); i < part.end(); ++i) {
                          for (int a = 0; a < 3; ++a) {
                            ranges[i][a] = cell_of(boxes[i].min()[a], a);
                            ranges[i][a + 3] = cell_of(boxes[i].max()[a], a);
                          }
                          first_entry[i + 1] = int64_t{ranges[i][3] - ranges[i][0] + 1} *
                                               (ranges[i][4] - ranges[i][1] + 1) *
                                               (ranges[i][5] - ranges[i][2] + 1);
                        }
                      });
    std::partial_sum(first_entry.begin(), first_entry.end(), first_entry.begin());
    entries.resize(first_entry[n]);
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096),
                      [&](const tbb::blocked_range<int>& part) {
                        for (int i = part.begin(); i < part.end(); ++i) {
                          int64_t e = first_entry[i];
                          for (int64_t x = ranges[i][0]; x <= ranges[i][3]; ++x)
                            for (int64_t y = ranges[i][1]; y <= ranges[i][4]; ++y)
                              for (int64_t z = ranges[i][2]; z <= ranges[i][5]; ++z)
                                entries[e++] = {CellKey(x, y, z), i};
                        }
                      });
    for (int a = 0; a < 3; ++a) last_cell[a] = cell_of(all.max()[a], a);
    // By cell (z, then y, then x: the keys' order), each cell's triangles
    // ascending as they were entered.
    RadixSort(&entries, BitsBelow(NumCells()),
              [&](const std::pair<uint64_t, int>& e) { return DenseCellOfKey(e.first); });
  }

  // Whether `box` overlaps a cell that holds a triangle (or, for a box over
  // many cells, the grid's bounds).
  bool Touches(const Eigen::AlignedBox3d& box) const {
    int64_t low[3], high[3], cells = 1;
    for (int a = 0; a < 3; ++a) {
      low[a] = static_cast<int64_t>(std::floor((box.min()[a] - origin[a]) / cell));
      high[a] = static_cast<int64_t>(std::floor((box.max()[a] - origin[a]) / cell));
      if (!(high[a] >= 0 && low[a] <= last_cell[a])) return false;  // NaN: outside
      low[a] = std::max<int64_t>(low[a], 0);
      high[a] = std::min(high[a], last_cell[a]);
      cells *= high[a] - low[a] + 1;
    }
    if (cells > kMaxCellsPerQuery) return true;
    for (int64_t x = low[0]; x <= high[0]; ++x)
      for (int64_t y = low[1]; y <= high[1]; ++y)
        for (int64_t z = low[2]; z <= high[2]; ++z) {
          if (!occupied.empty()) {
            const uint64_t c = DenseCell(x, y, z);
            if (occupied[c >> 6] >> (c & 63) & 1) return true;
            continue;
          }
          const auto it = std::lower_bound(entries.begin(), entries.end(),
                                           std::make_pair(CellKey(x, y, z), -1));
          if (it != entries.end() && it->first == CellKey(x, y, z)) return true;
        }
    return false;
  }

  // Marks the cells holding triangles in a bitmap over the grid (if it has
  // at most kMaxDenseCells cells), for Touches to read.
  void MarkOccupied() {
    if (NumCells() > kMaxDenseCells) return;
    occupied.assign((NumCells() + 63) / 64, 0);
    for (const auto& [key, triangle] : entries) {
      const uint64_t c = DenseCellOfKey(key);
      occupied[c >> 6] |= uint64_t{1} << (c & 63);
    }
  }
  // The grid's cells, numbered x fastest then y then z (the keys' order).
  uint64_t NumCells() const {
    return uint64_t(last_cell[0] + 1) * (last_cell[1] + 1) * (last_cell[2] + 1);
  }
  uint64_t DenseCell(uint64_t x, uint64_t y, uint64_t z) const {
    return x + (last_cell[0] + 1) * (y + (last_cell[1] + 1) * z);
  }
  uint64_t DenseCellOfKey(uint64_t key) const {
    constexpr uint64_t kAxis = (uint64_t{1} << 21) - 1;  // CellKey's bits per axis
    return DenseCell(key & kAxis, (key >> 21) & kAxis, key >> 42);
  }

  // The triangles j > i (positions in `selected`) that share a cell with
  // triangle i, ascending.
  void Neighbours(int i, std::vector<int>* candidates) const {
    candidates->clear();
    for (int64_t x = ranges[i][0]; x <= ranges[i][3]; ++x)
      for (int64_t y = ranges[i][1]; y <= ranges[i][4]; ++y)
        for (int64_t z = ranges[i][2]; z <= ranges[i][5]; ++z) {
          // Entries of the cell past (cell, i): the cell's triangles j > i.
          auto it =
              std::upper_bound(entries.begin(), entries.end(), std::make_pair(CellKey(x, y, z), i));
          for (; it != entries.end() && it->first == CellKey(x, y, z); ++it) {
            candidates->push_back(it->second);
          }
        }
    std::sort(candidates->begin(), candidates->end());
    candidates->erase(std::unique(candidates->begin(), candidates->end()), candidates->end());
  }

  // The pairs (i < j, positions in `selected`) that cross, among those that
  // `wanted(i, j)` accepts, ascending. Each pair of triangles sharing cells
  // is met once, in the first cell of the overlap of their cell ranges, so
  // cells are walked in parallel without looking triangles up or removing
  // duplicates.
  template <typename Wanted>
  std::vector<std::pair<int, int>> CrossingPairs(const TriangleMesh& mesh,
                                                 const std::vector<int>& selected,
                                                 const Wanted& wanted) const;
};

// Crossing pairs (indices into mesh.triangles, first < second by position in
// `selected`), ordered by first then second; stops after max_pairs (< 0:
// all). Returns the count found. Triangles are bucketed in a uniform grid
// (TriangleGrid); the triangles are tested in parallel when every pair is
// wanted, each one's pairs kept in order, so the result does not depend on
// scheduling.
bool ShareVertex(const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  bool shared = false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) shared = shared || a[i] == b[j];
  return shared;
}

// Does triangle i of `grid` cross triangle j (positions in `selected`)? The
// boxes' overlap is tested by the caller.
bool GridPairCrosses(const TriangleMesh& mesh, const std::vector<int>& selected,
                     const TriangleGrid& grid, int i, int j) {
  return !ShareVertex(mesh.triangles[selected[i]], mesh.triangles[selected[j]]) &&
         TrianglesCross(TriangleOf(mesh, selected[i]), grid.planes[i],
                        TriangleOf(mesh, selected[j]), grid.planes[j], grid.scale);
}

template <typename Wanted>
std::vector<std::pair<int, int>> TriangleGrid::CrossingPairs(const TriangleMesh& mesh,
                                                             const std::vector<int>& selected,
                                                             const Wanted& wanted) const {
  std::vector<size_t> starts;  // of each cell's run of entries, then the end
  for (size_t e = 0; e < entries.size(); ++e) {
    if (e == 0 || entries[e].first != entries[e - 1].first) starts.push_back(e);
  }
  starts.push_back(entries.size());
  // A cell's triangles, their boxes and the lowest cell of their ranges,
  // copied side by side for the pair loop.
  struct Local {
    std::vector<int> triangle;
    std::vector<Eigen::AlignedBox3f> box;
    std::vector<std::array<int32_t, 3>> low;
  };
  tbb::enumerable_thread_specific<std::vector<std::pair<int, int>>> found;
  tbb::enumerable_thread_specific<Local> locals;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, starts.size() - 1, 64),
                    [&](const tbb::blocked_range<size_t>& cells) {
                      std::vector<std::pair<int, int>>& mine = found.local();
                      Local& local = locals.local();
                      for (size_t c = cells.begin(); c < cells.end(); ++c) {
                        const uint64_t cell = entries[starts[c]].first;
                        local.triangle.clear(), local.box.clear(), local.low.clear();
                        for (size_t e = starts[c]; e < starts[c + 1]; ++e) {
                          const int i = entries[e].second;
                          local.triangle.push_back(i);
                          local.box.push_back(boxes[i]);
                          local.low.push_back({ranges[i][0], ranges[i][1], ranges[i][2]});
                        }
                        const size_t k = local.triangle.size();
                        for (size_t p = 0; p < k; ++p) {
                          const std::array<int32_t, 3>& a = local.low[p];
                          for (size_t q = p + 1; q < k; ++q) {
                            const std::array<int32_t, 3>& b = local.low[q];
                            // Met in an earlier cell, or apart.
                            if (CellKey(std::max(a[0], b[0]), std::max(a[1], b[1]),
                                        std::max(a[2], b[2])) != cell ||
                                !local.box[p].intersects(local.box[q])) {
                              continue;
                            }
                            const int i = local.triangle[p],
                                      j = local.triangle[q];  // i < j: entries sorted
                            if (wanted(i, j) && GridPairCrosses(mesh, selected, *this, i, j)) {
                              mine.emplace_back(i, j);
                            }
                          }
                        }
                      }
                    });
  std::vector<std::pair<int, int>> pairs;
  for (const std::vector<std::pair<int, int>>& part : found) {
    pairs.insert(pairs.end(), part.begin(), part.end());
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

int64_t SelfIntersections(const TriangleMesh& mesh, const std::vector<int>& selected,
                          int64_t max_pairs, std::vector<std::pair<int, int>>* pairs) {
  if (selected.size() < 2) return 0;
  const int n = static_cast<int>(selected.size());
  const TriangleGrid grid(mesh, selected);
  // The pairs (i, j > i) of triangle i, j ascending.
  const auto pairs_of = [&](int i, std::vector<int>* candidates, std::vector<int>* found) {
    grid.Neighbours(i, candidates);
    for (int j : *candidates) {
      if (grid.boxes[i].intersects(grid.boxes[j]) && GridPairCrosses(mesh, selected, grid, i, j)) {
        found->push_back(j);
      }
    }
  };
  int64_t count = 0;
  if (max_pairs >= 0) {  // few pairs wanted: in order, stopping early
    std::vector<int> candidates, found;
    for (int i = 0; i < n; ++i) {
      found.clear();
      pairs_of(i, &candidates, &found);
      for (int j : found) {
        ++count;
        if (pairs != nullptr) pairs->emplace_back(selected[i], selected[j]);
        if (count >= max_pairs) return count;
      }
    }
    return count;
  }
  const std::vector<std::pair<int, int>> found =
      grid.CrossingPairs(mesh, selected, [](int, int) { return true; });
  if (pairs != nullptr) {
    for (const auto& [i, j] : found) pairs->emplace_back(selected[i], selected[j]);
  }
  return static_cast<int64_t>(found.size());
}

// Triangles whose material is named `material` (all if empty).
std::vector<int> SelectTriangles(const TriangleMesh& mesh, const std::string& material) {
  int material_idx = -1;
  if (!material.empty()) {
    for (size_t m = 0; m < mesh.materials.size(); ++m) {
      if (mesh.materials[m].name == material) material_idx = static_cast<int>(m);
    }
  }
  std::vector<int> selected;
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    if (material.empty() || mesh.triangle_materials[t] == material_idx) selected.push_back(t);
  }
  return selected;
}

// Every triangle of `mesh`, in order.
std::vector<int> AllTriangles(const TriangleMesh& mesh) {
  std::vector<int> all(mesh.NumTriangles());
  std::iota(all.begin(), all.end(), 0);
  return all;
}

// The triangles of `mesh` whose boxes share a cell of `fresh`'s grid with a
// triangle of `fresh` (which are among them), ascending.
std::vector<int> NearTriangles(const TriangleMesh& mesh, const std::vector<int>& fresh) {
  TriangleGrid fresh_grid(mesh, fresh);
  fresh_grid.MarkOccupied();
  std::vector<char> near(mesh.NumTriangles(), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.NumTriangles(), 4096),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int t = range.begin(); t < range.end(); ++t) {
                        Eigen::AlignedBox3d box;
                        for (int k = 0; k < 3; ++k) {
                          box.extend(mesh.vertices[mesh.triangles[t][k]].cast<double>());
                        }
                        near[t] = fresh_grid.Touches(box);
                      }
                    });
  for (int t : fresh) near[t] = 1;
  std::vector<int> selected;
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    if (near[t]) selected.push_back(t);
  }
  return selected;
}

// The crossing pairs (a < b) of `mesh` with a triangle of `fresh`
// (ascending), tested in parallel on a grid of the triangles near them, with
// the tolerances of the whole mesh (`scale`).
std::vector<std::pair<int, int>> PairsWithFresh(const TriangleMesh& mesh,
                                                const std::vector<int>& fresh, double scale) {
  if (fresh.empty()) return {};
  const std::vector<int> selected = NearTriangles(mesh, fresh);
  const TriangleGrid grid(mesh, selected, scale);
  std::vector<char> is_fresh(selected.size(), 0);
  for (size_t i = 0, k = 0; i < selected.size() && k < fresh.size(); ++i) {
    if (fresh[k] == selected[i]) {
      is_fresh[i] = 1;
      ++k;
    }
  }
  std::vector<std::pair<int, int>> pairs =
      grid.CrossingPairs(mesh, selected, [&](int i, int j) { return is_fresh[i] || is_fresh[j]; });
  for (auto& [a, b] : pairs) {
    a = selected[a];  // ascending with the positions
    b = selected[b];
  }
  return pairs;
}

// The extent of the mesh's triangles (TriangleGrid::scale over all of them).
double TrianglesScale(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3i& f : mesh.triangles) {
    for (int k = 0; k < 3; ++k) box.extend(mesh.vertices[f[k]].cast<double>());
  }
  return box.isEmpty() ? 0.0 : std::max(box.sizes().maxCoeff(), 1e-30);
}

}  // namespace

namespace {

// A hash of triangle t's vertex positions (their bits), from `seed`.
uint64_t HashOf(const TriangleMesh& mesh, int t, uint64_t seed) {
  uint64_t hash = seed;
  for (int k = 0; k < 3; ++k) {
    for (int a = 0; a < 3; ++a) {
      uint32_t bits;
      std::memcpy(&bits, &mesh.vertices[mesh.triangles[t][k]][a], sizeof(bits));
      hash = (hash ^ bits) * 0x100000001b3ULL;
      hash ^= hash >> 29;
    }
  }
  return hash;
}

}  // namespace

// Each triangle of the new mesh's index in the old one (-1: new), matching
// the sorted hashes; a hash held by two triangles of either mesh matches
// nothing.
std::vector<int> CrossingTracker::Match(const std::vector<Hashed>& old_hashes,
                                        const std::vector<Hashed>& hashes) {
  std::vector<int> previous(hashes.size(), -1);
  const auto same = [](const Hashed& x, const Hashed& y) {
    return x.first == y.first && x.second == y.second;
  };
  const auto unique_at = [&](const std::vector<Hashed>& list, size_t i) {
    return (i == 0 || !same(list[i - 1], list[i])) &&
           (i + 1 == list.size() || !same(list[i + 1], list[i]));
  };
  const auto before = [](const Hashed& x, const Hashed& y) {
    return x.first != y.first ? x.first < y.first : x.second < y.second;
  };
  for (size_t i = 0, j = 0; i < hashes.size() && j < old_hashes.size();) {
    if (before(hashes[i], old_hashes[j])) {
      ++i;
    } else if (before(old_hashes[j], hashes[i])) {
      ++j;
    } else {
      if (unique_at(hashes, i) && unique_at(old_hashes, j)) {
        previous[hashes[i].triangle] = old_hashes[j].triangle;
      }
      ++i, ++j;
    }
  }
  return previous;
}

// Sorted by (first, second, triangle): bucketed by the first hash's top
// bits (the hashes are uniform, so a few per bucket), then each bucket
// sorted. One scatter instead of a radix sort's four.
void CrossingTracker::SortHashes(std::vector<Hashed>* hashes) {
  constexpr int kBucketBits = 16;
  std::vector<size_t> start((size_t{1} << kBucketBits) + 1, 0);
  const auto bucket = [](const Hashed& h) { return h.first >> (64 - kBucketBits); };
  for (const Hashed& h : *hashes) ++start[bucket(h) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<Hashed> sorted(hashes->size());
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (const Hashed& h : *hashes) sorted[next[bucket(h)]++] = h;
  for (size_t b = 0; b + 1 < start.size(); ++b) {
    if (start[b + 1] - start[b] > 1) {
      std::sort(sorted.begin() + start[b], sorted.begin() + start[b + 1]);
    }
  }
  hashes->swap(sorted);
}

std::vector<std::pair<int, int>> CrossingTracker::Find(const TriangleMesh& mesh) {
  mesh.Check();
  const int n = mesh.NumTriangles();
  std::vector<Hashed> hashes(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& part) {
    for (int t = part.begin(); t < part.end(); ++t) {
      hashes[t] = {HashOf(mesh, t, 0xcbf29ce484222325ULL), HashOf(mesh, t, 0x84222325cbf29ce4ULL),
                   t};
    }
  });
  SortHashes(&hashes);
  const std::vector<int> previous = Match(hashes_, hashes);
  const int64_t kept = n - std::count(previous.begin(), previous.end(), -1);
  const double scale = TrianglesScale(mesh);
  std::vector<std::pair<int, int>> pairs;
  if (2 * kept < n || scale != scale_) {  // mostly new, or another extent (tolerances)
    SelfIntersections(mesh, AllTriangles(mesh), -1, &pairs);
    last_tested_ = n;
  } else {
    std::vector<int> now_of(hashes_.size(), -1);  // previous index -> index now
    std::vector<int> fresh;
    for (int t = 0; t < n; ++t) {
      if (previous[t] >= 0) now_of[previous[t]] = t;
      if (previous[t] < 0) fresh.push_back(t);
    }
    for (const auto& [a, b] : pairs_) {
      const int na = now_of[a], nb = now_of[b];
      if (na < 0 || nb < 0 || ShareVertex(mesh.triangles[na], mesh.triangles[nb])) continue;
      pairs.emplace_back(std::min(na, nb), std::max(na, nb));
    }
    const std::vector<std::pair<int, int>> fresh_pairs = PairsWithFresh(mesh, fresh, scale);
    pairs.insert(pairs.end(), fresh_pairs.begin(), fresh_pairs.end());
    std::sort(pairs.begin(), pairs.end());
    last_tested_ = static_cast<int64_t>(fresh.size());
  }
  hashes_ = std::move(hashes);
  pairs_ = pairs;
  scale_ = scale;
  return pairs;
}

std::vector<std::pair<int, int>> FindSelfIntersections(const TriangleMesh& mesh,
                                                       const std::string& material,
                                                       int64_t max_pairs) {
  mesh.Check();
  std::vector<std::pair<int, int>> pairs;
  SelfIntersections(mesh, SelectTriangles(mesh, material), max_pairs, &pairs);
  return pairs;
}

bool MeshCheck::IsClosedManifold() const {
  return triangles > 0 && boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 &&
         degenerate_triangles == 0 && self_intersections <= 0;
}

std::string MeshCheck::BriefReport() const {
  std::ostringstream out;
  out << "Mesh check: " << triangles << " triangles, " << components << " components";
  if (inside_out_components > 0) out << " (" << inside_out_components << " INSIDE OUT)";
  out << ", " << boundary_edges << " boundary / " << nonmanifold_edges << " non-manifold / "
      << misoriented_edges << " misoriented edges, " << degenerate_triangles
      << " degenerate triangles, ";
  if (self_intersections < 0) {
    out << "self-intersections not checked";
  } else {
    out << self_intersections << " self-intersecting pairs";
  }
  out << ", volume " << volume << ", area " << area << " ("
      << (IsClosedManifold() ? "closed manifold" : "NOT a closed manifold") << ").";
  return out.str();
}

MeshCheck CheckMesh(const TriangleMesh& mesh, const std::string& material,
                    bool self_intersections) {
  mesh.Check();
  const std::vector<int> selected = SelectTriangles(mesh, material);
  MeshCheck check;
  check.triangles = static_cast<int>(selected.size());
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3f& v : mesh.vertices) bounds.extend(v.cast<double>());
  const double scale = mesh.vertices.empty() ? 1.0 : std::max(bounds.sizes().maxCoeff(), 1e-30);

  std::unordered_map<int64_t, int> undirected, directed;
  const int64_t n = mesh.NumVertices();
  std::vector<int> parent(mesh.NumVertices());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> used(mesh.NumVertices(), 0);
  for (int t : selected) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>();
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    check.area += 0.5 * cross.norm();
    check.volume += a.dot(b.cross(c)) / 6.0;
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
        0.5 * cross.norm() <= kEpsilon * kEpsilon * scale * scale) {
      ++check.degenerate_triangles;
    }
    for (int k = 0; k < 3; ++k) {
      const int u = f[k], v = f[(k + 1) % 3];
      ++directed[u * n + v];
      ++undirected[std::min(u, v) * n + std::max(u, v)];
      used[u] = 1;
      const int ru = Find(&parent, u), rv = Find(&parent, v);
      if (ru != rv) parent[ru] = rv;
    }
  }
  for (const auto& [edge, count] : undirected) {
    if (count == 1) ++check.boundary_edges;
    if (count > 2) ++check.nonmanifold_edges;
  }
  for (const auto& [edge, count] : directed) {
    if (count > 1) ++check.misoriented_edges;
  }
  std::unordered_map<int, double> component_volume;
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    if (used[v] && Find(&parent, v) == v) {
      ++check.components;
      component_volume[v] = 0.0;
    }
  }
  // Signed volumes relative to the bounds' centre (not the origin): each
  // component's is the same either way when it is closed, and the sums lose
  // fewer digits far from the origin.
  const Eigen::Vector3d centre = mesh.vertices.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                                       : Eigen::Vector3d(bounds.center());
  for (int t : selected) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>() - centre;
    const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>() - centre;
    const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>() - centre;
    component_volume[Find(&parent, f[0])] += a.dot(b.cross(c)) / 6.0;
  }
  for (const auto& [root, volume] : component_volume) {
    if (volume < 0) ++check.inside_out_components;
  }
  if (self_intersections) check.self_intersections = SelfIntersections(mesh, selected, -1, nullptr);
  return check;
}

int TurnInsideOutComponents(TriangleMesh* mesh) {
  mesh->Check();
  const int64_t n = mesh->NumVertices();
  std::vector<int> parent(mesh->NumVertices());
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<int64_t, int> undirected;
  for (const Eigen::Vector3i& f : mesh->triangles) {
    for (int k = 0; k < 3; ++k) {
      const int u = f[k], v = f[(k + 1) % 3];
      ++undirected[std::min(u, v) * n + std::max(u, v)];
      const int ru = Find(&parent, u), rv = Find(&parent, v);
      if (ru != rv) parent[ru] = rv;
    }
  }
  std::unordered_map<int, char> open;
  for (const auto& [edge, count] : undirected) {
    if (count != 2) open[Find(&parent, static_cast<int>(edge / n))] = 1;
  }
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3f& v : mesh->vertices) bounds.extend(v.cast<double>());
  const Eigen::Vector3d centre = mesh->vertices.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                                        : Eigen::Vector3d(bounds.center());
  std::unordered_map<int, double> volume;
  for (const Eigen::Vector3i& f : mesh->triangles) {
    const Eigen::Vector3d a = mesh->vertices[f[0]].cast<double>() - centre;
    const Eigen::Vector3d b = mesh->vertices[f[1]].cast<double>() - centre;
    const Eigen::Vector3d c = mesh->vertices[f[2]].cast<double>() - centre;
    volume[Find(&parent, f[0])] += a.dot(b.cross(c)) / 6.0;
  }
  int turned = 0;
  for (const auto& [root, v] : volume) turned += v < 0 && !open.count(root) ? 1 : 0;
  if (turned == 0) return 0;
  for (Eigen::Vector3i& f : mesh->triangles) {
    const int root = Find(&parent, f[0]);
    if (volume[root] < 0 && !open.count(root)) std::swap(f[1], f[2]);
  }
  return turned;
}

}  // namespace sylva
