// The wood of a tree from its skeleton: optional twigs grown on it
// (mesh/twigs.h), the bark as one watertight surface (mesh/bark_mesh.h) or
// as one overlapping tube per branch axis (mesh/branch_mesh.h), and the
// twigs joined to the bark or as closed tubes of their own. The mesh stage
// (ui/pipeline/tree_building.h) and `sylva mesh-qsm`
// (ui/pipeline/qsm_meshing.h) both mesh through MeshWood.
#ifndef SYLVA_MESH_WOOD_H_
#define SYLVA_MESH_WOOD_H_

#include <string>

#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "mesh/bark_mesh.h"
#include "mesh/twigs.h"

namespace sylva {

struct WoodOptions {
  // The bark as one watertight surface (MeshBarkWatertight with `bark`);
  // false: one overlapping closed tube per branch axis (MeshBranches with
  // bark.tube). BranchMesh.watertight.
  bool watertight_bark = true;
  // bark.tube: the tubes' options (BranchMesh.*), also of separate twigs.
  BarkMeshOptions bark;
  // Grow twigs before meshing (Twigs.enabled); `twig` and `twig_mesh` say
  // how and how they are meshed (joined or separate, mesh/twigs.h).
  bool twigs = false;
  TwigOptions twig;
  TwigMeshOptions twig_mesh;
};

struct Wood {
  SkeletonGraph skeleton;  // the input with its twigs, if grown (leaves grow on it)
  TriangleMesh bark;       // with the twigs when they are joined
  TriangleMesh twigs;      // separate twig tubes (material twig_mesh.material); else empty
  // Of the watertight bark (watertight_bark only). Its components are
  // 1 + bark_summary.unattached per root (see mesh/bark_mesh.h).
  BarkMeshSummary bark_summary;
  std::string brief;  // the twigs' and the bark's summaries
};

// The skeleton the wood is meshed on (and the leaves grow on): the input
// with its twigs, if options.twigs (density drives their number, see
// GrowTwigs), and what growing them did.
struct GrownSkeleton {
  SkeletonGraph skeleton;
  TwigSummary twigs;
  std::string brief;  // the twigs' summary, or empty
};
GrownSkeleton GrowWoodSkeleton(const SkeletonGraph& skeleton, const DensityGrid& density,
                               const WoodOptions& options);

// Meshes the bark of a grown skeleton and, if separate, the twig tubes.
Wood MeshGrownWood(GrownSkeleton grown, const WoodOptions& options);

// Both steps: grows the twigs and meshes the wood. Throws InputError for
// bad options or skeletons.
Wood MeshWood(const SkeletonGraph& skeleton, const DensityGrid& density,
              const WoodOptions& options);

}  // namespace sylva

#endif  // SYLVA_MESH_WOOD_H_
