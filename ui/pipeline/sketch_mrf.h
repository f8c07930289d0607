// A tree from a drawing by Chen et al. 2008 (sketch/branch_mrf.h) instead of
// the particle flow: `sylva sketch DRAWING OUT_DIR --Sketch.method=mrf`.
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
#include "sketch/branch_mrf.h"
#include "sketch/drawing.h"
#include "sketch/sketch_views.h"

namespace sylva {

struct PipelineOptions;
struct QsmMeshing;
struct QsmModel;

struct SketchMrfOptions {
  // "flow" (the drawing as views of a project, the particle flow) or "mrf".
  std::string method = "flow";
  MrfOptions mrf;
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

struct MrfSketchTree {
  SkeletonGraph skeleton;  // with pipe-model radii, world units (m)
  MrfResult result;
  std::string template_name;
  ImageSet drawing_cameras;  // as sketch_cameras.json
  std::string brief;
};

// The tree of `drawings` (the first one is used; more views are not yet
// read by this method). Throws InputError naming the drawing if it has no
// branch and no crown to infer branches from.
MrfSketchTree MakeMrfSketchTree(const std::vector<SketchDrawing>& drawings,
                                const PipelineOptions& options,
                                const std::vector<TreeExemplar>& exemplars);

// tree.skeleton as a cylinder table (*qsm), meshed like a QSM with leaves
// on its thin branches (MeshSkeletonTree, qsm_meshing.h: BranchMesh.*,
// Leaves.*, whose command defaults UseSkeletonTreeDefaults gives).
QsmMeshing MeshMrfSketchTree(const MrfSketchTree& tree, const PipelineOptions& options,
                             QsmModel* qsm);

// Writes OUT_DIR/skeleton.json, sketch_cameras.json and the tree meshed by
// MeshMrfSketchTree (WriteQsmMeshing's files); returns the paths.
std::vector<std::filesystem::path> WriteMrfSketchTree(const MrfSketchTree& tree,
                                                      const QsmModel& qsm,
                                                      const QsmMeshing& meshing,
                                                      const PipelineOptions& options,
                                                      const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_SKETCH_MRF_H_
