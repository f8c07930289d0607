// A project made from drawings alone (issue 14): `sylva init PROJECT
// --sketch DRAWING...` and `sylva sketch`. Each drawing becomes a view
// (sketch/sketch_views.h): its rendering as the photo, its silhouette with
// the enclosed regions filled as the matte, an orthographic camera, and its
// branch strokes as the view's attractor strokes (edits/<view>.strokes.json).
// The project is then an ordinary one: the same stages make the tree, and a
// person edits it as any other (paint density, redraw strokes, re-run).
//
//   PROJECT/sketch/            the drawings as given, and
//   PROJECT/sketch/sketch_cameras.json   the drawn views' cameras at the
//                              drawings' canvas sizes (core/io/camera_file.h),
//                              to project the tree back onto the drawings
#ifndef SYLVA_UI_PIPELINE_SKETCH_PROJECT_H_
#define SYLVA_UI_PIPELINE_SKETCH_PROJECT_H_

#include <filesystem>
#include <vector>

#include "sketch/sketch_views.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/project.h"

namespace sylva {

struct SketchSetup {
  fs::path root;
  std::vector<fs::path> drawings;  // 1 to 4: front, side, back, other side
  int ndjson_index = 0;            // which drawing of a Quick, Draw! file
};

// The drawn views' camera file of a sketch project.
fs::path SketchCamerasPath(const Project& project);

// What a sketch project changes from the defaults, set in `registry`
// before the user's options: the drawn strokes are the attractors
// (Attractors.mode=edits), the drawn foot is the world origin and the
// drawings are upright (WorldFrame.*=keep, Skeleton.base=0,0,0), and leaves
// reach farther from the thin branches (a drawn crown is full).
void SetSketchDefaults(OptionRegistry* registry);

// Reads the drawings (sketch/drawing_io.h), makes their views and creates
// the project, saving the options `registry` holds. Throws InputError
// naming the drawing or option at fault; nothing is left behind on error.
Project CreateSketchProject(const SketchSetup& setup, const SketchViewOptions& options,
                            const OptionRegistry& registry);

// The same for drawings already read (`setup.drawings` are only copied into
// PROJECT/sketch/, and may be empty).
Project CreateSketchProject(const SketchSetup& setup, const std::vector<SketchDrawing>& drawings,
                            const SketchViewOptions& options, const OptionRegistry& registry);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_SKETCH_PROJECT_H_
