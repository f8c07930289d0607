// The fidelity report: how well the reconstruction reproduces the mattes,
// per view, for input and held-out views separately (thesis 7.2.2 uses
// silhouette precision and recall).
#ifndef SYLVA_UI_PIPELINE_REPORT_H_
#define SYLVA_UI_PIPELINE_REPORT_H_

#include <filesystem>
#include <string>
#include <vector>

#include <map>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "core/util/warning.h"
#include "datasets/eval/silhouette_metrics.h"
#include "mesh/leaves.h"
#include "mesh/tree_metrics.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {

struct ViewFidelity {
  std::string name;
  bool held_out = false;
  int downsample_factor = 1;
  int width = 0, height = 0;  // of the compared (downsampled) images
  SilhouetteScores scores;    // the density's projection
  FloatImage predicted;       // projected opacity
  FloatImage observed;        // downsampled matte
  bool has_mesh = false;
  SilhouetteScores mesh_scores;  // the mesh's rendered silhouette
  FloatImage mesh_coverage;
  FloatImage mesh_render;        // shaded RGBA picture of the mesh from this view
  // The stages' warnings about this view (a distrusted or repaired matte).
  std::vector<Warning> warnings;
};

// Facts about the reconstructed tree (world units of the project).
struct TreeMetrics {
  double height = 0;                // top of the mesh above the skeleton's root
  double crown_width = 0;           // largest horizontal extent of the leaves (or mesh)
  double trunk_radius = 0;          // root radius (an allometric prior)
  double total_branch_length = 0;   // sum of skeleton edge lengths
  std::vector<int> branches_per_order;  // branch axes of order 0, 1, ...
  int num_skeleton_nodes = 0;
  int num_triangles = 0;
};

struct FidelityGroup {
  int num_views = 0;
  double mean_iou = 0, min_iou = 0, mean_precision = 0, mean_recall = 0;
};

struct FidelityReport {
  std::vector<ViewFidelity> views;
  FidelityGroup input, held_out;            // density
  FidelityGroup mesh_input, mesh_held_out;  // mesh (if any)
  bool has_tree = false;
  TreeMetrics tree;
  // The mesh stage's tree metrics (out/metrics.json), for report.html's
  // "Tree" section.
  bool has_metrics = false;
  TreeMetricsReport metrics;
  // Preview pictures of the tree (Report.previews), written as
  // out/report/preview_<k>.png.
  std::vector<FloatImage> previews;
  // Every stage's warnings (core/util/warning.h), in pipeline order; those
  // about one view are also in that view's ViewFidelity::warnings.
  std::vector<Warning> warnings;
  // Grid facts.
  double voxel_size = 0;
  int64_t num_voxels = 0;
  Box3d bounds;
  std::string units;

  // Printed at the end of `sylva run`.
  std::string BriefReport() const;
};

// Projects `grid` into every view of `image_set` (one ray per downsampled
// pixel, at ReportOptions::pixels_per_voxel) and compares with `mattes`
// (full resolution, one per view).
FidelityReport ComputeFidelity(const DensityGrid& grid, const ImageSet& image_set,
                               const std::vector<FloatImage>& mattes,
                               const std::vector<bool>& held_out,
                               const ReportOptions& options);

// Adds `warnings` to the report, and each one about a view (its subject) to
// that view too.
void AddWarnings(const std::vector<Warning>& warnings, FidelityReport* report);

// Renders `mesh` (Embree) from every view of `image_set` at the resolution
// each view was compared at, and compares its coverage with the matte; also
// keeps a shaded picture of each view (if options.write_images). Adds the
// tree's metrics.
void AddMeshFidelity(const TriangleMesh& mesh, const SkeletonGraph& skeleton,
                     const ImageSet& image_set, const ReportOptions& options,
                     FidelityReport* report);

TreeMetrics ComputeTreeMetrics(const SkeletonGraph& skeleton, const TriangleMesh& mesh);

// Preview pictures of a tree (mesh/tree_preview.h) at Report.preview_size
// with Report.preview_samples_per_axis, 4 views (azimuths 0, 90, 180, 270
// degrees, 15 degrees up), white background, sRGB; none if Report.previews
// is off or the scene is empty. `leaves` (may be null) are drawn as instances.
std::vector<FloatImage> RenderReportPreviews(const TriangleMesh& bark, const LeafInstances* leaves,
                                             const ReportOptions& options);

// Writes dir/preview_<k>.png (k = 0, 1, ...) atomically; returns the paths.
std::vector<std::filesystem::path> WritePreviewPngs(const std::vector<FloatImage>& previews,
                                                    const std::filesystem::path& dir);

// out/report.json (+ out/report/*.png and out/report.html if asked); returns
// the files written. `stage_briefs` maps stage names to their summaries.
std::vector<std::filesystem::path> WriteFidelityReport(
    const FidelityReport& report, const std::map<std::string, std::string>& stage_briefs,
    const ReportOptions& options, const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_REPORT_H_
