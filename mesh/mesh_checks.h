// Topology and geometry checks of a TriangleMesh: is it a closed,
// consistently oriented 2-manifold without self-intersections, and what
// volume and area does it enclose?
//
// Vertices are identified by index, not by position: two vertices at the
// same place are different vertices (MeshBranches' overlapping tubes are each
// closed, and together they still count as closed).
#ifndef SYLVA_MESH_MESH_CHECKS_H_
#define SYLVA_MESH_MESH_CHECKS_H_

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/types/triangle_mesh.h"

namespace sylva {

struct MeshCheck {
  int triangles = 0;             // triangles checked (of the chosen material)
  int boundary_edges = 0;        // undirected edges used by exactly 1 triangle
  int nonmanifold_edges = 0;     // undirected edges used by 3 or more triangles
  int misoriented_edges = 0;     // directed edges used by 2 or more triangles
  int degenerate_triangles = 0;  // repeated vertex index or (near) zero area
  int components = 0;            // connected by shared vertices
  // Components whose signed volume is negative: closed pieces turned inside
  // out (their normals point inwards), which subtract from `volume`.
  int inside_out_components = 0;
  // Pairs of triangles without a shared vertex whose interiors cross (one's
  // edge pierces the other). Coplanar overlaps are not counted. -1 = not run.
  int64_t self_intersections = -1;
  double volume = 0.0;  // signed, divergence theorem; > 0 for outward normals
  double area = 0.0;

  // No boundary, non-manifold, misoriented edges or degenerate triangles,
  // at least one triangle, and no self-intersections if they were counted.
  bool IsClosedManifold() const;
  // One line for humans.
  std::string BriefReport() const;
};

// Checks the triangles of `mesh` whose material is named `material` (all
// triangles if empty; an unknown name checks none). The self-intersection
// test (a uniform grid over the triangles' bounds, then exact-enough
// segment-triangle tests with a relative epsilon of 1e-9) runs only if
// `self_intersections`. Throws Error for an invalid mesh (TriangleMesh::Check).
MeshCheck CheckMesh(const TriangleMesh& mesh, const std::string& material = "",
                    bool self_intersections = true);

// The crossing triangle pairs CheckMesh counts, as indices into
// mesh.triangles (each pair once, in a deterministic order), at most
// `max_pairs` of them (< 0: all). For diagnostics: where does a mesh cross?
std::vector<std::pair<int, int>> FindSelfIntersections(const TriangleMesh& mesh,
                                                       const std::string& material = "",
                                                       int64_t max_pairs = -1);

// FindSelfIntersections for a mesh built again and again with local changes
// (the watertight bark's repair rounds re-mesh a few junctions each round):
// a triangle identical to one of the previous mesh (the same three vertex
// positions, bit for bit, as two 64-bit hashes of them tell) keeps the
// crossings it had with the other
// identical ones, and only the pairs with a new triangle are tested, on a
// grid of the triangles that share a cell with a new one. Gives the pairs
// FindSelfIntersections gives (all triangles), in its order; the first call,
// and one where most triangles are new, tests the whole mesh.
class CrossingTracker {
 public:
  std::vector<std::pair<int, int>> Find(const TriangleMesh& mesh);
  // Triangles tested in the last Find (all of them for a whole-mesh search).
  int64_t last_tested() const { return last_tested_; }

 private:
  // Two hashes of a triangle's vertex positions, and the triangle.
  struct Hashed {
    uint64_t first = 0, second = 0;
    int triangle = -1;
    bool operator<(const Hashed& o) const {
      return first != o.first     ? first < o.first
             : second != o.second ? second < o.second
                                  : triangle < o.triangle;
    }
  };
  static void SortHashes(std::vector<Hashed>* hashes);
  static std::vector<int> Match(const std::vector<Hashed>& old_hashes,
                                const std::vector<Hashed>& hashes);
  // Of the previous mesh: its triangles' hashes (sorted), its crossings and
  // its extent.
  std::vector<Hashed> hashes_;
  std::vector<std::pair<int, int>> pairs_;
  double scale_ = 0.0;
  int64_t last_tested_ = 0;
};

// The one repair here: turns every closed component (connected by shared
// vertices, each of its edges used by exactly two of its triangles) whose
// signed volume is negative right side out, by reversing its triangles.
// Such a component is inside out whatever made it; open ones are left alone
// (their sign means nothing). Returns how many were turned.
int TurnInsideOutComponents(TriangleMesh* mesh);

}  // namespace sylva

#endif  // SYLVA_MESH_MESH_CHECKS_H_
