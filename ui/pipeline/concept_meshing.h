// `sylva concept DRAWING OUT_DIR` (issue 17, Anastacio et al. 2006): a
// concept sketch of a plant (construction lines and organ strokes,
// sketch/concept_sketch.h) becomes a 3D plant (sketch/concept_plant.h) and
// goes through the mesh stage's outputs: the stem and line organs as the
// watertight bark of the skeleton (MeshWood with BranchMesh.*), the blades
// as leaf surfaces (their midribs drawn as veins), glTF/OBJ, the skeleton, its QSM table, L-Py and
// MTG exports, previews, and pen-and-ink drawings of the plant (mesh/pen_and_ink.h) from the front
// (the drawing's own view), obliquely and from the top.
#ifndef SYLVA_UI_PIPELINE_CONCEPT_MESHING_H_
#define SYLVA_UI_PIPELINE_CONCEPT_MESHING_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/triangle_mesh.h"
#include "mesh/pen_and_ink.h"
#include "sketch/concept_plant.h"
#include "sketch/concept_sketch.h"
#include "sketch/drawing.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {

struct ConceptMeshing {
  ConceptStructure structure;
  ConceptPlant plant;
  TriangleMesh bark;  // the stem and line organs (closed solids)
  // The pen-and-ink views and their names ("front", "oblique", "top").
  std::vector<PenAndInkDrawing> drawings;
  std::vector<std::string> view_names;
  std::string brief;

  TriangleMesh Tree() const;  // bark + blades
};

// Interprets, builds and meshes the drawing with Concept.*, BranchMesh.*,
// PenAndInk.* and General.seed. Throws InputError naming the drawing or
// the option at fault; writes nothing.
ConceptMeshing MeshConceptDrawing(const SketchDrawing& drawing, const PipelineOptions& options);

// Writes into `out_dir` (created): tree.glb, tree.obj (+ .mtl), bark.obj
// (+ .mtl), skeleton.json, qsm.csv, tree.lpy, tree_turtle.lpy, tree.mtg,
// organs.json (the placed organs: node, azimuth, divergence from the
// previous organ, base, tip, length, fit), pen_<view>.svg and .png,
// metrics.json, if Report.previews preview_<k>.png, and the report of a plant
// made without photos (report.json, report.html: WriteFidelityReport); each
// file atomically. Returns the paths.
std::vector<std::filesystem::path> WriteConceptMeshing(const ConceptMeshing& meshing,
                                                       const std::filesystem::path& out_dir,
                                                       const PipelineOptions& options);

// All of it for `sylva concept`: reads the drawing (ReadSketch), meshes it,
// and writes the outputs to a staging folder beside `out_dir` that becomes
// `out_dir` only when complete (an empty existing `out_dir` is replaced; a
// non-empty one is an InputError). Nothing is left behind on error. The
// effective options (`registry`, over `options`) go to OUT_DIR/options.json.
ConceptMeshing RunConcept(const std::filesystem::path& drawing_path, int ndjson_index,
                          const std::filesystem::path& out_dir, const PipelineOptions& options,
                          const OptionRegistry& registry,
                          std::vector<std::filesystem::path>* written);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_CONCEPT_MESHING_H_
