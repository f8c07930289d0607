// Meshing a QSM cylinder table (e.g. TreeQSM's, from a laser scan) without a
// project: the table becomes sylva skeletons (one per root cylinder), each is
// meshed into the watertight bark of the mesh stage, and the outputs are the
// mesh stage's. `sylva mesh-qsm QSM.csv OUT_DIR` calls this.
#ifndef SYLVA_UI_PIPELINE_QSM_MESHING_H_
#define SYLVA_UI_PIPELINE_QSM_MESHING_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/qsm_io.h"
#include "core/types/triangle_mesh.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {

struct QsmMeshing {
  std::vector<QsmSkeleton> parts;  // one per root cylinder
  TriangleMesh bark;               // every part's bark (closed solids)
  // The bark's figures (mesh/mesh_checks.h): connected components, those
  // turned inside out, and its volume over the union of the cylinders
  // (QsmUnionVolume, which is also given).
  int components = 0;
  int inside_out_components = 0;
  // Closed components the mesher made inside out, turned right side out
  // before the figures above (TurnInsideOutComponents; 0 on every table
  // tested).
  int turned_components = 0;
  double cylinder_union_volume = 0.0;
  double volume_ratio = 0.0;
  std::string brief;
};

// `merge_fraction`: QsmToSkeletonOptions::merge_fraction (children whose
// start lies within this fraction of their radius of the parent's axis hang
// from it directly; avoids sub-millimetre connector edges of float32 tables).
// Children starting inside their parent cylinder always hang from it
// (merge_inside_parent), and the watertight bark's polygons have the
// circle's area (BranchMeshOptions::circle_area; the overlapping tubes of
// BranchMesh.watertight=false keep inscribed polygons and no bark figures
// in the brief). The brief and the figures below tell
// whether the bark is what it should be.
QsmMeshing MeshQsm(const QsmModel& qsm, const PipelineOptions& options, double merge_fraction);

// Writes OUT_DIR/bark.obj, tree.obj (+ .mtl), tree.glb, qsm.csv (the table
// as sylva read it, with its ids), metrics.json (of the largest part,
// TreeMetrics.*) and, if Report.previews, preview pictures of the bark
// OUT_DIR/preview_<k>.png
// (RenderReportPreviews), each atomically; creates OUT_DIR. Returns the
// paths written.
std::vector<std::filesystem::path> WriteQsmMeshing(const QsmMeshing& meshing, const QsmModel& qsm,
                                                   const std::filesystem::path& out_dir,
                                                   const PipelineOptions& options);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_QSM_MESHING_H_
