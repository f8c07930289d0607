// Loop subdivision of a closed triangle mesh (Loop 1987, "Smooth Subdivision
// Surfaces Based on Triangles"), for smoother bark junctions: each level
// splits every triangle into four and moves the vertices towards the limit
// surface, which is C2 except at extraordinary vertices (valence != 6).
//
// Rules (closed meshes only, so no boundary or crease rules):
//  - a new "odd" vertex on edge (a, b) whose two triangles' opposite corners
//    are c and d: 3/8 (a + b) + 1/8 (c + d);
//  - an old "even" vertex v of valence n with neighbours p_i:
//    (1 - n beta) v + beta sum p_i, with Warren's weights
//    beta = 3/16 for n = 3, else 3 / (8 n)
//    (Warren 1995, a simpler stand-in for Loop's
//    beta = (5/8 - (3/8 + 1/4 cos(2 pi / n))^2) / n with the same limit
//    smoothness in practice).
//
// Why our own code and not OpenSubdiv: Debian 12's libosd-dev 3.5.0 ships
// an OpenSubdivConfig.cmake whose targets name libosdCPU.a / libosdGPU.a,
// which the package does not contain, so find_package(OpenSubdiv) fails and
// it would need a Find module of our own; and our TriangleMesh carries only
// positions and per-triangle materials (no texture coordinates to refine as
// face-varying data), so the uniform Loop refinement is ~150 lines over a
// half-edge table, with no dependency.
//
// Loop subdivision is approximating: convex parts shrink, and thin tubes of
// few sides the most (their polygon rounds inwards). Measured after one
// level (mesh/subdivision_test.cc): a straight tube of 4 sides keeps 75 % of
// its volume, 6 sides 87 %, 8 sides 92 %, 12 sides 96 %, 24 sides 98.5 %;
// 8-sided bark of synthetic trees 93-94 %.
#ifndef SYLVA_MESH_SUBDIVISION_H_
#define SYLVA_MESH_SUBDIVISION_H_

#include <string>

#include "core/types/triangle_mesh.h"

namespace sylva {

// Each level multiplies the triangles by 4.
constexpr int kMaxLoopLevels = 3;

struct LoopSubdivisionSummary {
  int levels = 0;
  int input_triangles = 0;
  int triangles = 0;  // after subdivision
  int vertices = 0;   // after subdivision
  // Enclosed (signed) volumes before and after, in world units^3: Loop
  // subdivision shrinks convex parts, so volume / input_volume < 1.
  double input_volume = 0.0;
  double volume = 0.0;
  double seconds = 0.0;

  // One line for humans.
  std::string BriefReport() const;
};

// `levels` Loop subdivision steps of `mesh` (in [0, kMaxLoopLevels]; 0
// returns an unchecked copy). The mesh must be a closed, consistently oriented
// 2-manifold by vertex index (several components are fine): every undirected
// edge used by exactly two triangles in opposite directions, no triangle
// repeating a vertex, and the triangles around each vertex forming one fan.
// Otherwise throws InputError("mesh", ...) with the counts of offending
// edges / vertices. Vertex positions are welded by index, not by position.
// Each child triangle keeps its parent's material; materials are copied.
// Orientation is preserved. Deterministic (no hashing, fixed orders).
// `summary` may be null.
TriangleMesh SubdivideLoop(const TriangleMesh& mesh, int levels,
                           LoopSubdivisionSummary* summary = nullptr);

}  // namespace sylva

#endif  // SYLVA_MESH_SUBDIVISION_H_
