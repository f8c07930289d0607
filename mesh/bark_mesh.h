// One watertight bark surface for a whole skeleton (thesis 5.3).
//
// MeshBranches (mesh/branch_mesh.h) gives one closed tube per branch axis,
// and the tubes of laterals overlap their parent. MeshBarkWatertight instead
// returns ONE closed, consistently (outward) oriented 2-manifold:
//
//  1. Joints. Every node with two or more children is a junction. Around it
//     the incident edges ("exits": the edge to the parent and one per child)
//     are cut back: the cut cross-section of exit e is the circle of radius
//     r_e (the edge's radius) centred on the edge at distance t_e from the
//     node, perpendicular to the edge. t_e = sqrt(rho^2 - r_e^2) with rho the
//     radius of the enclosing sphere, the largest over all pairs of exits of
//     eq. 5.25 (r_sphere = r_1 / sin(alpha)), times (1 + sphere_margin), so
//     every cut circle lies on that sphere.
//  2. The joint surface is the convex hull of the cut rings' vertices, minus
//     the ring polygons: since every ring is a face of that hull, the hull's
//     remaining triangles connect the rings exactly along the rings' own
//     vertices and edges. Where the thesis connects the pair with the
//     smallest radius difference first and then bridges the rest, the hull
//     connects all rings at once (same surface for two exits; a convex
//     bridge for three or more). The hull is built by gift wrapping from the
//     ring edges (positions deterministically jittered by 1e-7 of the
//     joint's size to break ties of cocircular points).
//  3. Pieces. Between joints, tips and the root, every chain of
//     pass-through nodes becomes one open tube (mesh/branch_mesh.h
//     SampleTubeRings/AppendTube) whose B-spline runs from one cut centre
//     through the chain's nodes to the next cut centre. The spline's end
//     tangents lie along the cut edges, so its end rings are exactly the cut
//     rings. Tips and the root (if it is not a junction) get flat caps.
//
// Fallbacks (counted in the summary): a ring is a hull face only if every
// other ring lies strictly behind its plane; that is checked exactly (on the
// circles, so independent of the polygon's rotation). If it fails, the cuts
// of the joint are pushed out (x1.25, at most 8 times). If a cut does not fit
// on its edge (t_e > max_cut_fraction of the edge, or the two joints of one
// edge need more than that together), the joint absorbs the neighbouring
// node (it becomes part of the joint, whose exits are then the edges leaving
// the group; a tip absorbed this way is swallowed by the joint's convex
// hull) or merges with the neighbouring joint. Groups of several nodes use
// the same hull construction; their rings need not lie on one sphere.
// Near-parallel or crowded children therefore end up in a larger convex
// joint: closed and manifold, but fatter than the branches there.
#ifndef SYLVA_MESH_BARK_MESH_H_
#define SYLVA_MESH_BARK_MESH_H_

#include <string>

#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "mesh/branch_mesh.h"

namespace sylva {

struct BarkMeshOptions {
  // Rings, sides and bark material of the pieces, as for MeshBranches.
  BranchMeshOptions tube;
  // The enclosing sphere of eq. 5.25 is enlarged by this fraction so that
  // neighbouring cut rings do not touch (> 0, <= 10).
  double sphere_margin = 0.15;
  // A cut may use at most this fraction of its edge (shared by the two
  // joints if both ends are joints); in (0, 1).
  double max_cut_fraction = 0.9;
  // Ring radii are at least this fraction of the largest radius, so tips of
  // radius 0 still give a valid ring (in (0, 1)).
  double min_radius_fraction = 0.01;
  // Laterals whose first edge has at most this fraction of the parent's
  // radius are attached to one quad of the parent tube (see above) instead
  // of a convex joint around the whole junction; in [0, 1], 0 = never.
  double attach_ratio = 1.0;

  // Throws InputError("BarkMesh.<field>", ...) naming the violated constraint.
  void Check() const;
};

struct BarkMeshSummary {
  int junctions = 0;       // nodes with 2 or more children
  int joints = 0;          // convex joints built (junctions after merging)
  int bridged = 0;         // joints of a single junction node, cut on the sphere
  int fallbacks = 0;       // nodes absorbed into a joint or joints merged
  int pushed_out = 0;      // joints whose cuts had to be pushed beyond the sphere
  int swallowed_tips = 0;  // tips inside a joint (their branch is the hull)
  int attached = 0;        // thin laterals glued onto a quad of the parent tube
  int unattached = 0;      // thin laterals that found no quad: capped, overlapping (not closed)
  int failed_joints = 0;   // joints whose hull could not be built (mesh not closed)
  int pieces = 0;          // tubes between joints, tips and the root
  int triangles = 0;
  double seconds = 0.0;
  std::string radius_source;

  // One line for humans.
  std::string BriefReport() const;
};

// The watertight bark of `skeleton` (see the header comment), one material
// (options.tube.bark). `summary` may be null. Validates the skeleton like
// MeshBranches (InputError("skeleton", ...)). Deterministic.
TriangleMesh MeshBarkWatertight(const SkeletonGraph& skeleton, const BarkMeshOptions& options,
                                BarkMeshSummary* summary);

}  // namespace sylva

#endif  // SYLVA_MESH_BARK_MESH_H_
