// The fidelity report: how well the reconstruction reproduces the mattes,
// per view, for input and held-out views separately (the scores:
// datasets/eval/view_fidelity.h), with the tree's figures, previews and the
// stages' warnings; written as out/report.json and report.html.
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
#include "datasets/eval/view_fidelity.h"
#include "mesh/leaves.h"
#include "mesh/tree_metrics.h"
#include "ui/pipeline/pipeline_options.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {

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
  // <preview_dir>/preview_<k>.png beside report.json (out/report/ in a
  // project; the output folder itself for trees made without photos).
  std::vector<FloatImage> previews;
  std::string preview_dir = "report";
  // The earlier stages' figures (StageRun::figures, as recorded), in
  // pipeline order.
  std::vector<std::pair<std::string, std::vector<StageFigure>>> stage_figures;
  // Every stage's warnings (core/util/warning.h), in pipeline order; those
  // about one view are also in that view's ViewFidelity::warnings.
  std::vector<Warning> warnings;
  // Grid facts.
  double voxel_size = 0;
  int64_t num_voxels = 0;
  Box3d bounds;
  std::string units;

  // Views that are priors, not photographs (ViewFidelity::prior).
  int NumPriorViews() const;

  // Printed at the end of `sylva run`.
  std::string BriefReport() const;
};

// The report of the density's fidelity (ComputeDensityViewFidelity with
// the Report options, and its input and held-out groups) and the grid's
// facts. `projections`: as ComputeDensityViewFidelity's.
FidelityReport ComputeFidelity(const DensityGrid& grid, const ImageSet& image_set,
                               const std::vector<FloatImage>& mattes,
                               const std::vector<bool>& held_out, const ReportOptions& options,
                               std::vector<FloatImage>* projections = nullptr);

// Flags the views named `names` as priors (ViewFidelity::prior: a drawing's
// made-up depth view) and leaves them out of every group's figures.
void MarkPriorViews(const std::vector<std::string>& names, FidelityReport* report);

// Adds `warnings` to the report, and each one about a view (its subject) to
// that view too.
void AddWarnings(const std::vector<Warning>& warnings, FidelityReport* report);

// The report's own warnings, when a group of views is poorly reproduced
// (mean IoU below Report.poor_fit_iou): "poor-density-fit" (the density
// against the input views' mattes) and "poor-mesh-fit" (the tree's
// silhouette against them), each saying whether the matte's foreground is
// missed (recall) or exceeded (precision) and what usually causes it. None
// for a report without views. A wrong tree is then named in the summary and
// the report instead of only showing in its figures.
std::vector<Warning> FidelityWarnings(const FidelityReport& report, const ReportOptions& options);

// Adds the mesh's fidelity (AddMeshViewFidelity with the Report options,
// and its groups) to a report of ComputeFidelity on the same views.
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
// the files written. A report without views (a tree made without photos:
// gestures, a drawing by MRF, a QSM or MTG) holds the tree's figures,
// previews and summaries only. `stage_briefs` maps stage names to their summaries.
std::vector<std::filesystem::path> WriteFidelityReport(
    const FidelityReport& report, const std::map<std::string, std::string>& stage_briefs,
    const ReportOptions& options, const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_REPORT_H_
