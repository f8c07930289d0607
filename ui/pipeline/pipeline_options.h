// All options of a sylva run, one struct per algorithm, and their
// registration in the option registry (the single place that names them for
// users as Section.field).
#ifndef SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_
#define SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "mesh/allometry.h"
#include "mesh/bark_mesh.h"
#include "mesh/branch_mesh.h"
#include "mesh/leaves.h"
#include "mesh/pen_and_ink.h"
#include "mesh/tree_metrics.h"
#include "mesh/twigs.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/density/density_options.h"
#include "reconstruct/matting/matte_set.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/measurement/branch_width.h"
#include "reconstruct/registration/colmap_runner.h"
#include "reconstruct/registration/loose_registration.h"
#include "reconstruct/registration/world_frame.h"
#include "simulate/attractor_field.h"
#include "simulate/particle_flow.h"
#include "simulate/skeleton_consolidation.h"
#include "simulate/skeleton_pruning.h"
#include "sketch/concept_plant.h"
#include "sketch/gesture_options.h"
#include "sketch/sketch_views.h"
#include "sketch/stroke_graph.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/sketch_mrf.h"

namespace sylva {

struct GeneralOptions {
  // Seed of every random choice of the run; same inputs and seed give the
  // same tree. Each stage derives its own stream from it.
  uint64_t seed = 1;
  // Worker threads; 0 uses every core.
  int num_threads = 0;
  void Check() const;
};

// The skeleton stage's own settings around the particle flow and radii.
struct SkeletonOptions {
  // The bottom of the trunk, in world units; NaN (the default, "auto") =
  // estimated from the density (TreeBase options).
  Eigen::Vector3d base = Eigen::Vector3d::Constant(NAN);
  // Radius of the trunk at its base, in world units; 0 = measured in the
  // mattes, or trunk_radius_fraction x tree height where it cannot be.
  double trunk_radius = 0.0;
  double trunk_radius_fraction = 0.025;
  // The thinnest branch radius, as a fraction of the trunk radius.
  double min_radius_fraction = 0.02;
  // Removal of thin branches whose path leaves the mattes.
  MattePruningOptions pruning;
  // Then redundant twigs, bare sticks and thin branches at the trunk's foot
  // go (simulate/skeleton_consolidation.h).
  ConsolidationOptions consolidation;
  void Check() const;
};

struct ReportOptions {
  // A pixel of the projected density or rendered mesh is foreground at this
  // opacity (coverage) or more.
  double opacity_threshold = 0.5;
  // A matte pixel is foreground at this alpha or more.
  double matte_threshold = 0.5;
  // Mattes and projections are compared after downsampling so that a voxel
  // covers about this many pixels across (independent of the density stage's
  // own sampling, so that solver settings are compared on equal terms).
  double pixels_per_voxel = 1.0;
  // Rays per compared pixel along each axis when rendering the mesh.
  int mesh_samples_per_axis = 4;
  // Write per-view comparison pictures, renders and report.html under out/.
  bool write_images = true;
  // Preview pictures of the tree (mesh/tree_preview.h: bark and instanced
  // leaves, sun with shadows + sky, 4 views around it at 15 degrees
  // elevation) in out/report/preview_<k>.png, shown in report.html; also
  // written by `sylva mesh-qsm`.
  bool previews = true;
  // Width and height of the preview pictures, pixels, in [64, 4096].
  // report.html shows them 320 px wide, so 320 (with 2 x 2 rays per pixel)
  // is what a person sees, at a quarter of the rays of 640 (issue 18); raise
  // it for a high-DPI screen or print.
  int preview_size = 320;
  // Rays per preview pixel along each axis (anti-aliasing), in [1, 8].
  int preview_samples_per_axis = 2;
  // Below this mean IoU over the input views (unitless, in [0, 1]) the report
  // warns poor-density-fit / poor-mesh-fit (FidelityWarnings); 0 = never.
  double poor_fit_iou = 0.6;
  void Check() const;
};

// The matte stage's settings beyond the matting algorithm's own.
struct MatteStageOptions {
  // A photo of the backdrop without the tree (same size as the photos), for
  // Matting.trimap=difference; a path absolute or relative to the project.
  std::string background_photo;
};

// The mesh stage's settings beyond the meshers' own (thesis 5.3-5.4).
struct TreeGeometryOptions {
  // One closed, 2-manifold bark mesh with joints at the junctions
  // (mesh/bark_mesh.h); false = one overlapping tube per branch axis.
  bool watertight_bark = true;
  BarkMeshOptions bark;  // its `tube` is BranchMesh.*
  // Levels of Loop subdivision of the bark (mesh/subdivision.h) for smooth
  // junctions; 0 = off, at most kMaxLoopLevels (3). Each level multiplies
  // the bark's triangles by 4 and shrinks branches of few sides (after one
  // level a 4-sided branch keeps ~75 % of its volume, 8 sides ~92 %, 24 ~98 %).
  int bark_subdivision = 0;
  // Twigs grown from the terminal branches in proportion to density before
  // leaves are placed (mesh/twigs.h). Off by default: they multiply the
  // wood's triangles about sixfold (~800 twigs on a synthetic tree).
  bool twigs = false;
  TwigOptions twig;
  // Twigs joined to the bark, or as separate closed tubes beside it (many
  // twigs; mesh/twigs.h): Twigs.mesh, Twigs.separate_above.
  TwigMeshOptions twig_mesh;
  // A leaf picture (RGBA, alpha = the leaf's outline) used as a textured
  // leaf instead of Leaves.shape; a path absolute or relative to the project.
  std::string leaf_image;
  // Leaves in tree.glb as one leaf mesh + per-leaf transforms
  // (EXT_mesh_gpu_instancing); false = baked triangles.
  bool instance_leaves = true;
  void Check() const;
};

// The attract stage's settings (ui/pipeline/attract_stage.cc).
struct AttractStageOptions {
  // "auto": graphs from edits/ where a person made them, else traced by
  // livewire; "edits": only those made by a person (the other views have
  // none); "off": no attractor graphs (the flow follows the density alone).
  std::string mode = "auto";
  // Snap drawn strokes onto the photo's structures by livewire.
  bool snap_strokes = false;
  // Draw every graph on its photo (out/attractors/<photo>.png).
  bool write_overlays = true;
  StrokeGraphOptions strokes;
  LivewireOptions livewire;
  void Check() const;
};

struct PipelineOptions {
  GeneralOptions general;
  MattingOptions matting;
  MatteStageOptions matte_stage;
  MatteSetOptions matte_set;
  ColmapOptions colmap;
  WorldFrameOptions world_frame;
  LooseInitOptions loose_init;
  LooseRefineOptions loose_refine;
  DensityOptions density;
  TreeBaseOptions tree_base;
  AttractStageOptions attract;
  AttractorFieldOptions direction_field;
  ParticleFlowOptions particle_flow;
  SkeletonOptions skeleton;
  AllometryOptions allometry;
  BranchWidthOptions branch_width;
  BranchMeshOptions branch_mesh;
  LeafOptions leaves;
  TreeGeometryOptions geometry;
  TreeMetricsOptions tree_metrics;
  ReportOptions report;
  // How drawings become views (used when a sketch project is made).
  SketchViewOptions sketch;
  // Branches of a drawing by MRF (Sketch.method=mrf, sketch_mrf.h).
  SketchMrfOptions sketch_mrf;
  // How a concept sketch becomes a plant (`sylva concept`; its seed is
  // General.seed) and how it is drawn in pen and ink.
  ConceptPlantOptions concept_plant;
  PenAndInkOptions pen_and_ink;
  // How 3D gestures grow a tree (`sylva gesture`; its seed is General.seed).
  GestureTreeOptions gesture;

  // Throws InputError naming the first invalid option.
  void Check() const;
};

// Registers every user-facing field of `options` (which must outlive the
// registry). Seeds and the allometry's world-unit sizes are set by the
// stages from General.seed and Skeleton.* instead.
void RegisterPipelineOptions(PipelineOptions* options, OptionRegistry* registry);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_
