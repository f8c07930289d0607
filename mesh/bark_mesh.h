// The watertight bark of a whole skeleton (thesis 5.3).
//
// MeshBranches (mesh/branch_mesh.h) gives one closed tube per branch axis,
// and the tubes of laterals overlap their parent. MeshBarkWatertight instead
// glues open tubes (mesh/branch_mesh.h SampleTubeRings/AppendTube on
// B-splines) to "joints" that share their ring vertices exactly, into
// closed, consistently (outward) oriented 2-manifolds.
//
// What is promised: with summary.failed_joints == 0 the bark is closed,
// 2-manifold and outward, and has exactly 1 + summary.unattached connected
// components: the tree's, and one per thin lateral that found no free quad
// on its parent's tube and whose junction could not be made a convex joint
// either (its joint would grow too large, see 4., or the attempts ran out).
// Such a lateral, with everything growing from it, is a closed surface of
// its own, capped at its base and overlapping the parent (its triangles
// cross the parent's). The brief counts them ("N NOT attached:
// overlapping"). Measured: none on the synthetic trees (seeds 1-3) and the ITSMe
// tables but buttressed_tree_1 (2); 161 of the bundled demo's 817
// junctions (a dense particle-flow skeleton). Not promised: freedom from
// self-intersections (see the known gap below).
//
// How:
//
//  1. Attached laterals (the common case). At a junction of two children
//     whose lateral has at most attach_ratio of the parent's radius (default
//     1: any lateral thinner than its parent), the parent axis runs through
//     as one tube. Each lateral is cut back along its own chain until its cut ring
//     sees one quad of the parent tube (the quad its first edge's ray leaves
//     through) as the opposite face of their convex hull: every quad vertex
//     behind the ring's plane, every ring vertex in front of the quad's
//     triangles. The quad's two triangles are removed and the convex hull of
//     quad + ring, minus quad and ring, fills the gap. The quad and its
//     neighbours are then reserved, so joints of different laterals do not
//     share parent quads; a parent tube with two or more laterals at one
//     node gets at least 3 sides per lateral, so there are quads for all.
//     This replaces the thesis' pairwise bridging for thin laterals; the
//     cut distance comes from the quad test, not eq. 5.25.
//  2. Convex joints (the root junction, junctions of 3+ children, laterals
//     as thick as the parent, and laterals that found no free quad: then
//     everything is meshed again with that junction as a convex joint). A
//     junction of 3+ children whose joint grows over more than 4 nodes (see
//     3.) attaches its laterals one by one instead (meshed again; at most 8
//     rounds in all). The incident edges
//     ("exits": to the parent and to each child) are cut back along their
//     chains at t_e = sqrt(rho^2 - r_e^2), rho the enclosing-sphere radius of
//     eq. 5.25 (largest over pairs of exits at the node) times
//     (1 + sphere_margin), so the cut rings lie on one sphere. The joint is
//     the convex hull of all cut rings' vertices minus the ring polygons; each
//     ring must be a hull face, which is checked exactly (every other ring
//     strictly behind its plane); where it fails the offending cuts are
//     pushed out (x1.25, at most 16 times). Where the thesis connects the
//     pair with the smallest radius difference first and bridges the rest,
//     the hull connects all rings at once.
//  3. Fallback merges (counted): a cut that does not fit on its chain
//     (beyond max_cut_fraction of it, or the two ends' cuts of one chain
//     together) merges the chain's nodes into the joint; a tip reached that
//     way is swallowed by the joint's hull.
// Hulls are built by gift wrapping from the ring edges, the positions
// deterministically jittered by 1e-7 of the joint's size to break ties of
// cocircular points. Tips and a non-junction root get flat caps.
//
//  4. Repairs. A thin lateral is cut back until its first rings are
//     outside the parent tube, not only in front of the quad. After
//     meshing, the crossing triangle pairs (mesh/mesh_checks.h) are looked
//     up: junctions of crossing attachments, and the junction within 4 radii
//     of a crossing, are meshed again as convex joints (repair_rounds).
//     A repair whose joint swallows more than 8 nodes is undone.
//  5. Tight bends. Tube rings that fold against the previous ring (the axis
//     bends more sharply than the radius allows, as at QSM kinks) are
//     dropped: the longest run of unfolded rings is kept, from the first
//     ring where a joint or attachment uses it (else a capped end's ring may
//     go too, so a tube never comes out inside out).
//
// Known gap (ClassifyBarkCrossings, mesh/bark_crossings.h): the synthetic trees still have 0-31
// crossing pairs per ~100k triangles at junctions (next to twig clusters),
// and more where branches of the skeleton itself pass through each other,
// which no junction mesher can mend.
#ifndef SYLVA_MESH_BARK_MESH_H_
#define SYLVA_MESH_BARK_MESH_H_

#include <string>
#include <vector>

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
  // of a convex joint around the whole junction; in [0, 1], 0 = never
  // (convex joints only: on dense trees most junctions then merge).
  double attach_ratio = 1.0;
  // Rounds of repairs (see 4. above): after meshing, junctions next to
  // crossing triangles are meshed again as convex joints; each round costs
  // one self-intersection check and one meshing. 0 = no repairs; <= 16.
  int repair_rounds = 4;

  // Throws InputError("BranchMesh.<field>", ...) naming the violated constraint.
  void Check() const;
};

struct BarkMeshSummary {
  int junctions = 0;       // nodes with 2 or more children
  int joints = 0;          // convex joints built (junctions after merging)
  int bridged = 0;         // joints of a single junction node, cut on the sphere
  int fallbacks = 0;       // chains merged into a joint
  int pushed_out = 0;      // joints whose cuts had to be pushed beyond the sphere
  int swallowed_tips = 0;  // tips inside a joint (their branch is the hull)
  int attached = 0;        // thin laterals glued onto a quad of the parent tube
  // Thin laterals that found no quad (not even as a convex joint): each,
  // with its subtree, a closed component of its own, capped and overlapping
  // the parent (the bark has 1 + unattached components).
  int unattached = 0;
  int failed_joints = 0;  // joints whose hull could not be built (mesh not closed)
  int repaired = 0;       // junctions made convex joints because their triangles crossed
  int pieces = 0;         // tubes between joints, tips and the root
  int triangles = 0;
  double seconds = 0.0;
  std::string radius_source;

  // One line for humans.
  std::string BriefReport() const;
};

// What a bark triangle was made for (diagnostics: where does a mesh cross?).
struct BarkTriangleOrigin {
  enum Kind : int { kTube = 0, kAttachment = 1, kJoint = 2 };
  Kind kind = kTube;
  // kTube: the first two nodes of the tube's chain (its side and caps).
  // kAttachment: the junction and the attached lateral's first node.
  // kJoint: a node of the convex joint (the group's representative), -1.
  int node = -1;
  int next = -1;
};

// The watertight bark of `skeleton` (see the header comment), one material
// (options.tube.bark). `summary` and `origins` (one per triangle) may be
// null. Validates the skeleton like MeshBranches (InputError("skeleton",
// ...)). Deterministic.
TriangleMesh MeshBarkWatertight(const SkeletonGraph& skeleton, const BarkMeshOptions& options,
                                BarkMeshSummary* summary,
                                std::vector<BarkTriangleOrigin>* origins = nullptr);

}  // namespace sylva

#endif  // SYLVA_MESH_BARK_MESH_H_
