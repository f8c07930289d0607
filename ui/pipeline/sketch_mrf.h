// A tree from a drawing without the particle flow, by Chen et al. 2008
// (sketch/branch_mrf.h: `sylva sketch DRAWING OUT_DIR --Sketch.method=mrf`)
// or by Wither et al. 2009 (sketch/silhouette_tree.h:
// --Sketch.method=silhouette).
// MRF:
// The first drawing's branch strokes (drawn, or inferred from its crown as
// in sketch_views.h) become a segment tree on the drawing's plane; the
// template is the exemplar whose footprint is nearest; the MRF gives every
// segment's depth; self-similar propagation fills the drawn crown (its
// surface of local revolution) or grows Sketch.generations generations; the
// skeleton gets pipe-model radii and is meshed like a QSM with leaves on its
// thin branches (bark, leaves, glTF/OBJ, qsm.csv, metrics, L-Py, MTG,
// previews).
#ifndef SYLVA_UI_PIPELINE_SKETCH_MRF_H_
#define SYLVA_UI_PIPELINE_SKETCH_MRF_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "datasets/eval/silhouette_metrics.h"
#include "sketch/branch_mrf.h"
#include "sketch/drawing.h"
#include "sketch/silhouette_tree.h"
#include "sketch/sketch_views.h"

namespace sylva {

struct PipelineOptions;
struct QsmMeshing;
struct QsmModel;

struct SketchMrfOptions {
  // "flow" (the drawing as views of a project, the particle flow), "mrf" or
  // "silhouette".
  std::string method = "flow";
  MrfOptions mrf;
  SilhouetteTreeOptions silhouette;
  // Exemplar trees, comma-separated files: OpenAlea MTG (.mtg), TreeQSM
  // cylinder tables (.csv) or sylva skeletons (.json); empty = the built-in
  // species of the synthetic generator (BuiltinExemplars).
  std::string exemplars;
  void Check() const;  // throws InputError naming the option
};

// Four species of the synthetic generator (broadleaf, columnar, spreading,
// excurrent), one tree each, as exemplars. Deterministic.
std::vector<TreeExemplar> BuiltinExemplars();
// The exemplars of SketchMrfOptions::exemplars (each file's largest tree,
// up = +Z); throws InputError naming a file that cannot be read.
std::vector<TreeExemplar> LoadExemplars(const std::string& list);

// A tree made from drawings without a project.
struct SketchTree {
  SkeletonGraph skeleton;    // with pipe-model radii, world units (m)
  ImageSet drawing_cameras;  // as sketch_cameras.json
  // The first drawing's view (Sketch.image_size) and its matte: the drawing
  // with its enclosed regions filled, the crown at Sketch.crown_opacity.
  ImageSet front_view;
  FloatImage front_matte;
  std::string brief;
  // Where its positions and branching come from (qsm.csv, metrics.json).
  std::string position_source, branching_source;
};

struct MrfSketchTree : SketchTree {
  MrfResult result;
  std::string template_name;
};

// The tree of `drawings` (the first one is used; more views are not yet
// read by this method). Throws InputError naming the drawing if it has no
// branch and no crown to infer branches from.
MrfSketchTree MakeMrfSketchTree(const std::vector<SketchDrawing>& drawings,
                                const PipelineOptions& options,
                                const std::vector<TreeExemplar>& exemplars);

// Leaves of a silhouette tree are this share of its height long unless
// Leaves.leaf_length(_fraction) is given (the Leaves default, 1 %, left the
// drawn crowns' finest sub-silhouettes mostly empty).
constexpr double kSilhouetteLeafLengthFraction = 0.02;

// The tree of `drawings` by Wither 2009 (the first drawing is used): its
// crown outline (the largest region it encloses), its trunk (the branch
// stroke standing on the ground, else a vertical line from the base; taken
// up to 80 % of the crown's height), smaller closed crown strokes as
// sub-silhouettes and the other branch strokes as drawn branches. Throws
// InputError naming the drawing if it encloses no crown.
SketchTree MakeSilhouetteSketchTree(const std::vector<SketchDrawing>& drawings,
                                    const PipelineOptions& options);

// tree.skeleton as a cylinder table (*qsm), meshed like a QSM with leaves
// on its thin branches (MeshSkeletonTree, qsm_meshing.h: BranchMesh.*,
// Leaves.*, whose command defaults UseSkeletonTreeDefaults gives).
QsmMeshing MeshSketchTree(const SketchTree& tree, const PipelineOptions& options, QsmModel* qsm);

// How the meshed tree (bark and leaves) covers the drawing in its view: its
// coverage (at least half of a pixel) against the front matte (at least
// half the crown's opacity).
SilhouetteScores FrontViewFit(const SketchTree& tree, const QsmMeshing& meshing,
                              const PipelineOptions& options);

// Writes OUT_DIR/skeleton.json, sketch_cameras.json and the tree meshed by
// MeshSketchTree (WriteQsmMeshing's files); returns the paths.
std::vector<std::filesystem::path> WriteSketchTree(const SketchTree& tree, const QsmModel& qsm,
                                                   const QsmMeshing& meshing,
                                                   const PipelineOptions& options,
                                                   const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_SKETCH_MRF_H_
