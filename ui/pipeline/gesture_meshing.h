// `sylva gesture FILE OUT_DIR` (issue 17, Murakami et al.): 3D gestures
// (sketch/gesture_io.h) grow a tree by the interactive L-system under
// collision avoidance in the region of interest (sketch/gesture_tree.h),
// and the skeleton is meshed like a QSM (qsm_meshing.h) with leaves on its
// thin branches (AddSkeletonLeaves): bark, leaves, glTF/OBJ, qsm.csv,
// metrics, L-Py, MTG and previews, as `sylva sketch --Sketch.method=mrf`
// and `sylva mesh-qsm` write them.
#ifndef SYLVA_UI_PIPELINE_GESTURE_MESHING_H_
#define SYLVA_UI_PIPELINE_GESTURE_MESHING_H_

#include <filesystem>
#include <string>
#include <vector>

#include "sketch/gesture_io.h"
#include "sketch/gesture_tree.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/qsm_meshing.h"

namespace sylva {

struct GestureMeshing {
  GestureTree tree;
  std::string grammar_source;
  QsmModel qsm;  // the skeleton as a cylinder table (QsmFromSkeletonParts)
  QsmMeshing meshing;
  std::string brief;
};

// Grows (Gesture.*, General.seed) and meshes (BranchMesh.*, Geometry.*,
// Leaves.*: UseSkeletonTreeDefaults gives the command's defaults) the tree
// of `gestures`. Throws InputError naming the gesture file, the
// grammar file (line and column) or the option at fault; writes nothing.
GestureMeshing MeshGestures(const GestureSet& gestures, const PipelineOptions& options);

// Writes WriteQsmMeshing's files into `out_dir` (created) and
// skeleton.json, lstring.txt (the final L-string, corrected) and roi.json
// (the supertoroid); each file atomically. Returns the paths.
std::vector<std::filesystem::path> WriteGestureMeshing(const GestureMeshing& meshing,
                                                       const std::filesystem::path& out_dir,
                                                       const PipelineOptions& options);

// All of it for `sylva gesture`: reads the file (ReadGesture), grows and
// meshes, and writes to a staging folder beside `out_dir` that becomes
// `out_dir` only when complete (an empty existing `out_dir` is replaced; a
// non-empty one is an InputError); nothing is left behind on error. The
// effective options go to OUT_DIR/options.json.
GestureMeshing RunGesture(const std::filesystem::path& gesture_path,
                          const std::filesystem::path& out_dir, const PipelineOptions& options,
                          const OptionRegistry& registry,
                          std::vector<std::filesystem::path>* written);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_GESTURE_MESHING_H_
