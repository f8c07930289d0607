// The density stage (thesis 3.3): from mattes and cameras to a sparse grid
// of per-voxel opacity.
//
//  0. Views: a view whose matte disagrees with the others' consensus (an
//     inverted or half-empty matte would carve away what they agree on) is
//     left out and named (view_consensus.h).
//  1. Bounds: the visual hull's bounding box (or DensityOptions::bounds).
//  2. Initialisation and implicit carving: each voxel's opacity starts as the
//     minimum over views of the mean matte over its footprint; voxels below
//     DensityOptions::carve_threshold are dropped.
//  3. The linear system (eq. 3.2-3.3): every (downsampled) pixel ray gives
//        sum_i l_i x_i = -log(1 - alpha_pixel),
//     with x_i the optical depth of voxel i per voxel length and l_i the
//     ray's length inside voxel i in voxel units (exact traversal). The
//     thesis uses l_i = 1 for every voxel hit; path lengths remove the bias
//     of rays that clip voxel corners and equal 1 for a ray straight through.
//  4. Least squares by CGLS from the initialisation (rescaled to fit the
//     data), negatives clamped to empty (plus optional non-negative passes).
//  5. Output: alpha_i = 1 - exp(-x_i), stored where >= min_output_opacity.
#ifndef SYLVA_RECONSTRUCT_DENSITY_DENSITY_RECONSTRUCTION_H_
#define SYLVA_RECONSTRUCT_DENSITY_DENSITY_RECONSTRUCTION_H_

#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "core/util/warning.h"
#include "reconstruct/density/density_options.h"
#include "reconstruct/density/sparse_system.h"

namespace sylva {

// The app's loop re-solves after each density edit a system much like the
// last one: the previous solution is a better start than the matte
// initialisation. The caller keeps this between runs (the pipeline in the
// project's cache folder); the reconstruction uses it only when its key
// matches the new solve's, so a grid solved for other cameras, bounds or
// options is never used.
struct DensityWarmStart {
  // In: what the caller knows makes two solves comparable (the cameras and
  // the options, as canonical text); the reconstruction adds the grid's
  // block (dimensions, voxel size, corner) to form the key.
  std::string context;
  // In/out: the key the state below was solved under ("" for none); replaced
  // by this solve's key and state.
  std::string key;
  std::vector<int64_t> voxels;  // dense voxel indices of the unknowns, ascending
  std::vector<float> depths;    // their optical depths per voxel length
  // The projected gradient the solve stopped at (absolute): a warm solve stops
  // there, the same criterion as the solve it continues.
  double stop_gradient = 0.0;
};

struct DensitySummary {
  int num_views = 0;  // views used (trusted)
  // Views whose mattes disagree with the others and were left out
  // (view_consensus.h), with a "distrusted-view" warning each.
  std::vector<std::string> distrusted_views;
  int allowed_dissent = 0;           // views that may carve a consensus voxel away
  double median_carved_share = 0.0;  // share of the consensus the median view carves
  std::vector<Warning> warnings;
  bool automatic_bounds = true;
  Box3d bounds;  // world units
  // Views whose foreground reaches their image's edge (the tree goes on
  // beyond the frame): they do not bound the grid, unless no view frames
  // the tree whole (then a "frame-cut" warning).
  std::vector<std::string> frame_cut_views;
  bool cut_by_every_frame = false;
  Eigen::Vector3i grid_dims = Eigen::Vector3i::Zero();
  int resolution = 0;       // voxels along the longest side (Density.resolution or refined)
  double thin_share = 0.0;  // of the mattes' centre lines thinner than a voxel at it
  double voxel_size = 0.0;  // world units
  std::vector<int> downsample_factors;  // per view
  int64_t num_carved_voxels = 0;        // voxels kept by implicit carving (unknowns)
  int64_t num_rows = 0;                 // pixel-ray equations
  int64_t num_nonzeros = 0;
  int64_t num_unexplained_pixels = 0;  // foreground rays that hit no kept voxel
  double initial_scale = 1.0;          // factor applied to the initialisation
  int64_t num_warm_voxels = 0;         // unknowns started from the previous solve (warm start)
  std::vector<CglsSummary> solves;     // one per pass
  int64_t num_clamped_voxels = 0;      // negative values set to empty
  int64_t num_output_voxels = 0;
  double seconds_bounds = 0, seconds_init = 0, seconds_system = 0, seconds_solve = 0,
         seconds_total = 0;

  // One paragraph for humans (Ceres' BriefReport style).
  std::string BriefReport() const;
};

// Reconstructs the density grid from `mattes` (one single-channel alpha
// image per view of `image_set`, of the camera's size). Throws InputError
// naming the view for wrongly sized mattes, and for inconsistent cameras or
// when every matte is empty; Cancelled if `progress` asks to stop.
DensityGrid ReconstructDensity(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                               const DensityOptions& options, ProgressReporter* progress,
                               DensitySummary* summary);

// The same, starting the least squares from `warm_start`'s state where its
// key matches (unknowns it does not cover start from the initialisation)
// and stopping at its stop_gradient (or the usual tolerance), then leaving
// this solve's key and state in it. Null: a cold start.
DensityGrid ReconstructDensity(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                               const DensityOptions& options, ProgressReporter* progress,
                               DensitySummary* summary, DensityWarmStart* warm_start);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_DENSITY_RECONSTRUCTION_H_
