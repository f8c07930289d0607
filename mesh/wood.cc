#include "mesh/wood.h"

#include <sstream>

#include "mesh/branch_mesh.h"

namespace sylva {
namespace {

// The bark of `skeleton`, its summary appended to `brief`.
TriangleMesh MeshBark(const SkeletonGraph& skeleton, const WoodOptions& options,
                      BarkMeshSummary* bark_summary, std::ostream* brief) {
  if (options.watertight_bark) {
    TriangleMesh bark = MeshBarkWatertight(skeleton, options.bark, bark_summary);
    *brief << bark_summary->BriefReport();
    return bark;
  }
  BranchMeshSummary summary;
  TriangleMesh bark = MeshBranches(skeleton, options.bark.tube, &summary);
  *brief << summary.BriefReport();
  return bark;
}

// The twig tubes of `grown`, their summary appended to `brief`.
TriangleMesh MeshSeparateTwigs(const SkeletonGraph& grown, const TwigSummary& twigs,
                               const WoodOptions& options, std::ostream* brief) {
  const TwigMeshOptions& twig_mesh = options.twig_mesh;
  TwigTubesSummary tubes;
  TriangleMesh mesh = MeshTwigTubes(grown, twigs, options.bark.tube, twig_mesh, &tubes);
  *brief << "Twigs meshed apart (Twigs.mesh=" << twig_mesh.mode;
  if (twig_mesh.mode == "auto") *brief << ", more than " << twig_mesh.separate_above;
  *brief << "): " << tubes.BriefReport() << " ";
  return mesh;
}

}  // namespace

GrownSkeleton GrowWoodSkeleton(const SkeletonGraph& skeleton, const DensityGrid& density,
                               const WoodOptions& options) {
  GrownSkeleton grown;
  if (!options.twigs) {
    grown.skeleton = skeleton;
    return grown;
  }
  grown.skeleton = GrowTwigs(skeleton, density, options.twig, &grown.twigs);
  grown.brief = grown.twigs.BriefReport() + " ";
  return grown;
}

Wood MeshGrownWood(GrownSkeleton grown, const WoodOptions& options) {
  Wood wood;
  std::ostringstream brief;
  brief << grown.brief;
  wood.skeleton = std::move(grown.skeleton);
  if (options.twigs && options.twig_mesh.Separate(grown.twigs.twigs)) {
    wood.twigs = MeshSeparateTwigs(wood.skeleton, grown.twigs, options, &brief);
    wood.bark =
        MeshBark(RemoveTwigs(wood.skeleton, grown.twigs), options, &wood.bark_summary, &brief);
  } else {
    wood.bark = MeshBark(wood.skeleton, options, &wood.bark_summary, &brief);
  }
  wood.brief = brief.str();
  return wood;
}

Wood MeshWood(const SkeletonGraph& skeleton, const DensityGrid& density,
              const WoodOptions& options) {
  return MeshGrownWood(GrowWoodSkeleton(skeleton, density, options), options);
}

}  // namespace sylva
