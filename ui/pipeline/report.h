// The fidelity report: how well the reconstruction reproduces the mattes,
// per view, for input and held-out views separately (thesis 7.2.2 uses
// silhouette precision and recall).
#ifndef SYLVA_UI_PIPELINE_REPORT_H_
#define SYLVA_UI_PIPELINE_REPORT_H_

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
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
  FloatImage mesh_render;  // shaded RGBA picture of the mesh from this view
  // The stages' warnings about this view (a distrusted or repaired matte).
  std::vector<Warning> warnings;
};

// The scores of a group of views; absent (not 0) when the group has none.
struct FidelityGroup {
  int num_views = 0;
  std::optional<double> mean_iou, min_iou, mean_precision, mean_recall;
};

struct FidelityReport {
  std::vector<ViewFidelity> views;
  FidelityGroup input, held_out;            // density
  FidelityGroup mesh_input, mesh_held_out;  // mesh (if any)
  bool has_tree = false;                    // the mesh was compared
  int num_mesh_triangles = 0;
  // The tree's figures: the mesh stage's out/metrics.json (mesh/tree_metrics.h,
  // the one definition of each figure), as read back.
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

// The scores of `views` that are held out (or not), of the density (or of
// the mesh: views with has_mesh only).
FidelityGroup SummariseViews(const std::vector<ViewFidelity>& views, bool held_out, bool mesh);

// Projects `grid` into every view of `image_set` (one ray per downsampled
// pixel, at ReportOptions::pixels_per_voxel) and compares with `mattes`
// (full resolution, one per view).
FidelityReport ComputeFidelity(const DensityGrid& grid, const ImageSet& image_set,
                               const std::vector<FloatImage>& mattes,
                               const std::vector<bool>& held_out, const ReportOptions& options);

// Adds `warnings` to the report, and each one about a view (its subject) to
// that view too.
void AddWarnings(const std::vector<Warning>& warnings, FidelityReport* report);

// Renders `mesh` (Embree) from every view of `image_set` at the resolution
// each view was compared at, and compares its coverage with the matte; also
// keeps a shaded picture of each view (if options.write_images).
void AddMeshFidelity(const TriangleMesh& mesh, const ImageSet& image_set,
                     const ReportOptions& options, FidelityReport* report);

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
