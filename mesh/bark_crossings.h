// Where a watertight bark (mesh/bark_mesh.h) crosses itself, told by the
// skeleton: each crossing pair of triangles (mesh/mesh_checks.h
// FindSelfIntersections) is given the skeleton edges the two triangles were
// made for: an attachment's lateral edge, else the edge whose surface
// (distance to the edge minus its radius) is nearest the triangle's
// centroid, among its tube's axis (tubes) or all (joints). How far apart
// those edges are in the tree says whose the crossing is.
#ifndef SYLVA_MESH_BARK_CROSSINGS_H_
#define SYLVA_MESH_BARK_CROSSINGS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "mesh/bark_mesh.h"

namespace sylva {

struct BarkCrossings {
  int64_t pairs = 0;          // all crossing pairs
  int64_t within_branch = 0;  // both near the same edge (a kink in one tube)
  int64_t at_junctions = 0;   // edges 1-3 apart: a junction's pieces cross
  // Edges further apart whose skeleton capsules (segments with radii, or
  // those of their neighbouring edges) overlap: branches of the skeleton
  // itself pass through each other; no junction mesher can help there.
  int64_t colliding_branches = 0;
  int64_t other = 0;  // edges further apart whose capsules do not overlap

  std::string BriefReport() const;
};

// `bark` and `origins` from MeshBarkWatertight.
BarkCrossings ClassifyBarkCrossings(const SkeletonGraph& skeleton, const TriangleMesh& bark,
                                    const std::vector<BarkTriangleOrigin>& origins);

}  // namespace sylva

#endif  // SYLVA_MESH_BARK_CROSSINGS_H_
