// Meshing a QSM cylinder table (e.g. TreeQSM's, from a laser scan) without a
// project: the table becomes sylva skeletons (one per root cylinder), each is
// meshed into the watertight bark of the mesh stage, leaves may grow on the
// thin branches (AddSkeletonLeaves), and the outputs are the mesh stage's.
// `sylva mesh-qsm QSM.csv OUT_DIR` calls this, and `sylva mesh-mtg MTG
// OUT_DIR` after turning an OpenAlea MTG's skeletons into a table; so do the
// trees made without photos, `sylva gesture` and `sylva sketch
// --Sketch.method=mrf`, with their leaves.
#ifndef SYLVA_UI_PIPELINE_QSM_MESHING_H_
#define SYLVA_UI_PIPELINE_QSM_MESHING_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/mtg_io.h"
#include "core/io/qsm_io.h"
#include "core/types/triangle_mesh.h"
#include "mesh/leaves.h"
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
  // Leaves on the thin branches (AddSkeletonLeaves); none by MeshQsm.
  LeafInstances leaves;
  LeafSummary leaf_summary;
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

// Leaves on the thin branches of every part of `meshing`
// (GenerateSkeletonLeafInstances: Leaves.*, the seed from General.seed as
// LeafOptionsOf gives it) into meshing->leaves, unless Leaves.num_leaves is
// -1; their summary ends the brief. One leaf length for all parts:
// Leaves.leaf_length, or Leaves.leaf_length_fraction x the tallest part's
// height; branches are thin as a fraction of the tallest trunk's radius;
// part k > 0 draws from DeriveSeed(the leaves' seed, k). Leaves.image (a
// path relative to the working directory) replaces the built-in shape.
void AddSkeletonLeaves(const PipelineOptions& options, QsmMeshing* meshing);

// A skeleton made without photos (gestures, an MRF sketch) as a cylinder
// table (*qsm, QsmFromSkeletonParts in `units`), meshed (MeshQsm with
// `merge_fraction`) with leaves on its thin branches (AddSkeletonLeaves).
QsmMeshing MeshSkeletonTree(const SkeletonGraph& skeleton, const std::string& units,
                            double merge_fraction, const PipelineOptions& options, QsmModel* qsm);

// The defaults of trees made without photos (`sylva gesture`, `sylva sketch
// --Sketch.method=mrf`), set before the command's flags: their leaves show a
// phyllotaxis, Leaves.phyllotaxis = kSkeletonTreePhyllotaxis (the photo
// pipeline's "none" draws leaves where the density is, which these trees do
// not have).
inline constexpr char kSkeletonTreePhyllotaxis[] = "spiral";
void UseSkeletonTreeDefaults(PipelineOptions* options);
// The defaults of `sylva mesh-qsm` and `sylva mesh-mtg`: those of
// UseSkeletonTreeDefaults, and no leaves (Leaves.num_leaves = -1), since
// laser-scanned trees are mostly scanned leafless; --Leaves.num_leaves=0
// (one leaf per phyllotactic site) or N asks for them.
void UseQsmMeshingDefaults(PipelineOptions* options);

// Writes OUT_DIR/bark.obj, tree.obj (+ .mtl; the bark and the baked
// leaves), tree.glb (leaves instanced as by the mesh stage,
// Export.instance_leaves), qsm.csv (the table as sylva read it, with its
// ids), metrics.json (of the largest part,
// TreeMetrics.*), the table's exact skeletons (SkeletonsFromQsm) for plant
// modellers as tree.lpy, tree_turtle.lpy (core/io/lpy_io.h) and tree.mtg
// (core/io/mtg_io.h), if Report.previews preview pictures of the tree
// OUT_DIR/preview_<k>.png (RenderReportPreviews), and the report of a tree
// made without photos (report.json, report.html if Report.write_images: the
// figures, previews and the meshing's summary; WriteFidelityReport), each
// atomically; creates OUT_DIR. Returns the paths written.
std::vector<std::filesystem::path> WriteQsmMeshing(const QsmMeshing& meshing, const QsmModel& qsm,
                                                   const std::filesystem::path& out_dir,
                                                   const PipelineOptions& options);

// A table of skeleton parts: QsmFromSkeleton of each, the ids and branch
// ids of part k numbered after those of parts 0..k-1 (each part its own
// root). Parts need radii > 0 (QsmModel::Check).
QsmModel QsmFromSkeletonParts(const std::vector<SkeletonGraph>& parts, const std::string& units);

// How `sylva mesh-mtg` makes a cylinder table of an MTG.
struct MtgMeshingOptions {
  MtgToSkeletonOptions read;  // diameter_unit
  // Positions and radii are multiplied by this (e.g. 0.01 for the cm of
  // OpenAlea's digitised walnut, to metres). > 0.
  double scale = 1.0;
  // The unit of the scaled positions, for the outputs ("m", "cm", ...).
  std::string units = "unknown";
  // Files without radii get pipe-model radii (mesh/allometry.h) with this
  // trunk radius, in scaled units; 0 = kDefaultTrunkRadiusFraction x the
  // part's height. >= 0.
  double trunk_radius = 0.0;

  void Check() const;  // throws InputError naming the option
};

// The trunk radius of radius-less MTGs, as a fraction of the tree's height
// (a 5 m tree: 7.5 cm), when MtgMeshingOptions::trunk_radius is 0.
inline constexpr double kDefaultTrunkRadiusFraction = 0.015;
// The thinnest pipe-model radius given, as a fraction of the trunk's.
inline constexpr double kMinRadiusOfTrunk = 1.0 / 50;

struct MtgTable {
  MtgSkeletons read;                 // as read (unscaled)
  std::vector<SkeletonGraph> parts;  // scaled, every radius > 0
  QsmModel qsm;                      // QsmFromSkeletonParts(parts)
  int pipe_model_parts = 0;          // parts given pipe-model radii (no radius feature)
  int raised_radii = 0;              // radius-0 nodes raised to their part's smallest radius
  std::string brief;
};

// SkeletonsFromMtg, scaled, radii completed as above, as a cylinder table
// for MeshQsm. Throws InputError naming `source` for an unreadable tree.
MtgTable MtgTableForMeshing(const Mtg& mtg, const std::string& source,
                            const MtgMeshingOptions& options);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_QSM_MESHING_H_
