// The skeleton and mesh steps of the pipeline on in-memory data, shared by
// the stages (which read and write the project folder) and by tests.
#ifndef SYLVA_UI_PIPELINE_TREE_BUILDING_H_
#define SYLVA_UI_PIPELINE_TREE_BUILDING_H_

#include <ostream>
#include <string>
#include <vector>

#include "core/types/attractor_graph.h"
#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "core/util/progress.h"
#include "mesh/bark_mesh.h"
#include "mesh/leaves.h"
#include "mesh/wood.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {

struct BuiltSkeleton {
  SkeletonGraph skeleton;  // with pipe-model radii (an allometric prior)
  SkeletonGraph raw;       // the traces before simplification
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  double trunk_radius = 0;
  std::string brief;
  // The steps' times (base, field, flow with its own steps, pruning, ...).
  std::vector<StageStep> profile;
};

// Base (Skeleton.base or estimated), particle flow steered by the direction
// field of the attractor graphs (one per input view, empty = none; an empty
// list = no field), pruning of thin branches that leave the mattes, trunk
// radius (Skeleton.trunk_radius, or measured in the mattes, or a fraction of
// the height) and radii. `mattes` are the input views'. `painted_in`
// (optional; one per input view, empty images for views without density
// edits: Project::LoadPaintedIn) is where a person painted the tree in: the
// thin wood that carries that density is kept by the pruning and the
// consolidation (simulate/painted_density.h).
BuiltSkeleton BuildSkeleton(const DensityGrid& density, const ImageSet& input_views,
                            const std::vector<FloatImage>& mattes,
                            const std::vector<AttractorGraph2D>& attractors,
                            const PipelineOptions& options, ProgressReporter* progress,
                            const std::vector<FloatImage>* painted_in = nullptr);

// The tree's geometry: the wood (MeshWood, mesh/wood.h: the bark,
// watertight or tubes, BranchMesh.*, and grown twigs, Twigs.*), the bark
// smoothed by BranchMesh.subdivision levels of Loop subdivision, and the
// leaves as instances of one leaf shape (`shape`, may be null:
// Leaves.shape). Twigs are part of the bark (Twigs.mesh=joined) or closed
// tubes of their own in `twigs` (separate; mesh/twigs.h), whose bases sit
// inside the bark; either way the leaves grow on the skeleton with its
// twigs.
struct TreeGeometry {
  // Watertight: closed, outward solids, one plus one per lateral (or twig)
  // left unattached (bark_summary.unattached; mesh/bark_mesh.h).
  TriangleMesh bark;
  TriangleMesh twigs;            // separate twig tubes, material "twigs"; empty if joined or none
  LeafInstances leaves;          // empty for leafless plants
  BarkMeshSummary bark_summary;  // of the watertight bark (BranchMesh.watertight)
  std::string brief;
  // The steps' times (wood, subdivision, leaves).
  std::vector<StageStep> profile;
  // Bark + twigs + baked leaves.
  TriangleMesh Baked() const;
  // Bark + twigs (the wood, without leaves).
  TriangleMesh Wood() const;
};
TreeGeometry BuildTreeGeometry(const SkeletonGraph& skeleton, const DensityGrid& density,
                               const ImageSet& input_views, const std::vector<FloatImage>& mattes,
                               const PipelineOptions& options, const LeafShape* shape = nullptr);

// The wood's options (MeshWood) in the pipeline's: BranchMesh.* (the
// tubes of bark and separate twigs), Twigs.* with the twigs' seed derived
// from General.seed.
WoodOptions WoodOptionsOf(const PipelineOptions& options);

// The leaves' options in the pipeline's: Leaves.* with the leaves' seed
// derived from General.seed (the same stream for every kind of tree).
LeafOptions LeafOptionsOf(const PipelineOptions& options);

// Smooths `bark` by BranchMesh.subdivision levels of Loop subdivision
// (mesh/subdivision.h; nothing if 0) and appends its summary to `brief`.
// A bark that is not a closed 2-manifold (a failed joint, see
// BarkMeshSummary) is refused: InputError("BranchMesh.subdivision", ...).
void SubdivideBark(const TreeGeometryOptions& options, TriangleMesh* bark, std::ostream* brief);

// BuildTreeGeometry(...).Baked(); `brief` (may be null) receives the summaries.
TriangleMesh BuildTreeMesh(const SkeletonGraph& skeleton, const DensityGrid& density,
                           const ImageSet& input_views, const std::vector<FloatImage>& mattes,
                           const PipelineOptions& options, std::string* brief);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_TREE_BUILDING_H_
