// The fidelity report: how well the reconstruction reproduces the mattes,
// per view, for input and held-out views separately (thesis 7.2.2 uses
// silhouette precision and recall).
#ifndef SYLVA_UI_PIPELINE_REPORT_H_
#define SYLVA_UI_PIPELINE_REPORT_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "datasets/eval/silhouette_metrics.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {

struct ViewFidelity {
  std::string name;
  bool held_out = false;
  int downsample_factor = 1;
  int width = 0, height = 0;  // of the compared (downsampled) images
  SilhouetteScores scores;
  FloatImage predicted;  // projected opacity
  FloatImage observed;   // downsampled matte
};

struct FidelityGroup {
  int num_views = 0;
  double mean_iou = 0, min_iou = 0, mean_precision = 0, mean_recall = 0;
};

struct FidelityReport {
  std::vector<ViewFidelity> views;
  FidelityGroup input, held_out;
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

// out/report.json (+ out/report/*.png and out/report.html if asked); returns
// the files written. `density_brief` is the density stage's summary.
std::vector<std::filesystem::path> WriteFidelityReport(const FidelityReport& report,
                                                       const std::string& density_brief,
                                                       const ReportOptions& options,
                                                       const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_REPORT_H_
