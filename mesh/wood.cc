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

Wood MeshWood(const SkeletonGraph& skeleton, const DensityGrid& density,
              const WoodOptions& options) {
  Wood wood;
  std::ostringstream brief;
  TwigSummary twigs;
  wood.skeleton = options.twigs ? GrowTwigs(skeleton, density, options.twig, &twigs) : skeleton;
  if (options.twigs) brief << twigs.BriefReport() << " ";
  if (options.twigs && options.twig_mesh.Separate(twigs.twigs)) {
    wood.twigs = MeshSeparateTwigs(wood.skeleton, twigs, options, &brief);
    wood.bark = MeshBark(RemoveTwigs(wood.skeleton, twigs), options, &wood.bark_summary, &brief);
  } else {
    wood.bark = MeshBark(wood.skeleton, options, &wood.bark_summary, &brief);
  }
  wood.brief = brief.str();
  return wood;
}

}  // namespace sylva
