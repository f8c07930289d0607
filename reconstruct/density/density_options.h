// Options of the density stage (thesis 3.3): back-projection of mattes into a
// voxel grid and least squares on per-pixel log-transparency.
#ifndef SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_
#define SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_

#include <string>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

struct DensityOptions {
  // Voxels along the longest side of the reconstruction bounds. The thesis
  // used ~25; finer grids follow thin crowns better at a cubic memory cost.
  int resolution = 128;
  // Where more than max_thin_share of the mattes' centre lines lie in
  // structure thinner than a voxel (thin_structure.h), the grid is refined by
  // steps of 1.5x up to this many voxels, as long as the photos show the
  // finer voxels at least two pixels wide; a "thin-structure" warning says
  // when the cap is not enough. <= resolution: never refined.
  int max_resolution = 384;
  double max_thin_share = 0.1;

  // World-space bounds of the grid. Empty (the default) means automatic: the
  // bounding box of the visual hull of the mattes.
  Box3d bounds;
  // Margin added around automatic bounds, in voxels of the final grid.
  double bounds_margin_voxels = 1.0;
  // Voxels along the longest side of the coarse carving that finds the
  // automatic bounds.
  int hull_resolution = 64;
  // A pixel is foreground for the visual hull if its matte value exceeds
  // this (alpha, unitless).
  double hull_alpha_threshold = 0.05;
  // A photo's foreground reaching the image's edge means the tree goes on
  // beyond the frame (and may be wider there): such a photo does not bound
  // the automatic bounds (nor the view-consensus test's), the photos that
  // frame the tree whole do, or, where none does, a "frame-cut" warning says
  // the frames bound it (a synthetic crown cut at the top in 3 of 8 views:
  // 4.41 m tall instead of 6.32, held-out density IoU 0.536 -> 0.857).
  // False: the frames always bound the tree (drawings: their edge is the
  // drawing's, not a camera's).
  bool open_frame_cuts = true;

  // Wrong mattes (reconstruct/density/view_consensus.h): at most this share
  // of the views may be wrong, in [0, 0.5): the consensus hull keeps voxels
  // that at most floor(fraction x views) views carve away. 0 trusts every
  // view (the thesis' strict carving).
  double view_outlier_fraction = 0.2;
  // Fewer views than this are not tested (>= 3).
  int view_consensus_min_views = 5;
  // A view is distrusted (left out, and named in the summary) when it carves
  // away more than this share of the consensus hull it sees (in (0, 1]) ...
  double view_max_carved_share = 0.3;
  // ... and more than this many times the median view's share (> 1).
  double view_carved_share_ratio = 2.5;
  // Views a person painted density on (edits/density): the edit is the
  // person's word, so these views are never left out, however much they
  // disagree with the others (the summary then warns "edited-view-kept").
  // Set by the density stage, not an option.
  std::vector<std::string> edited_views;

  // Implicit carving (thesis 3.3): a voxel's initial opacity is the minimum
  // over views of the mean matte value over its footprint; voxels below this
  // opacity are dropped from the solve (alpha, unitless).
  double carve_threshold = 0.02;
  // Share of the views whose footprint may be (nearly) empty without carving
  // a voxel, in [0, 0.5): its initial opacity is the floor(carve_dissent x
  // views)-th lowest footprint mean instead of the lowest. Keeps structures
  // thinner than the registration error (a thin stem missed by a view or two)
  // for the least squares to decide; 0 = the thesis' minimum. Measured with
  // the defaults on ROMI's 22 real photos (siliques 1-2 mm, 3-4 dissenting
  // views at 0.2): density IoU input / held-out 0.499 / 0.479 at 0, 0.547 /
  // 0.497 at 0.1, 0.578 / 0.507 at 0.2, 0.598 / 0.515 at 0.3 (held-out
  // precision 0.925, 0.892, 0.872, 0.862: more floaters). With the real
  // demo's options (256 voxels, leafless) the mesh fits worse although the
  // density fits better: 0.147 -> 0.124 at 0.2.
  double carve_dissent = 0.2;
  // ... but at least this many views must see something at a voxel to keep
  // it: what fewer views agree on is mostly the visual hull's ghosts. With 8
  // exact synthetic views, one dissenting view kept ghosts that the particle
  // flow made into wood (leafless skeleton precision 0.825 -> 0.795, an
  // ITSMe tree's length 1.23 -> 1.39 x the truth).
  int carve_min_views = 8;

  // Images are box-downsampled by an integer factor so that one voxel covers
  // about this many pixels (across) at the grid centre; keeps the system
  // about as large as the grid.
  double pixels_per_voxel = 1.0;
  // Rays per downsampled pixel along each axis (n x n rays, averaged).
  int rays_per_axis = 1;
  // Matte opacities are clamped to this before -log(1 - alpha): a fully
  // opaque pixel would need an infinite optical depth (alpha, < 1).
  double max_pixel_opacity = 0.95;

  // Rows are weighted by max(1 - alpha_pixel, min_row_weight): to first
  // order this fits opacities rather than optical depths (d alpha / d depth =
  // 1 - alpha), so nearly opaque pixels, whose depth is clamped and
  // uncertain, do not dominate the fit. 1 = unweighted (thesis).
  double min_row_weight = 0.25;

  // How the least-squares system is solved:
  //   "projected": projected gradient with Barzilai-Borwein steps, keeping
  //                every optical depth >= 0 throughout (non-negative least
  //                squares; the default, see DESIGN notes in the report);
  //   "cgls":      the thesis' way: unconstrained least squares (CGLS), then
  //                negatives clamped to empty (plus nonnegative_passes).
  std::string solver = "projected";
  // Iterations per solve, and the stopping tolerance: |A^T r| / |A^T b| for
  // CGLS, the projected gradient relative to its start for "projected".
  int max_iterations = 50;
  // Solver "projected" only: every cauchy_every-th step is a Cauchy step
  // (sparse_system.h; 0 = Barzilai-Borwein steps only, the default). With
  // 3, 20 iterations reach the silhouette fit of 50 plain ones on the
  // synthetic trees, in 0.5x the solve's time (issue 18); not the default:
  // on ROMI's real photos the fit is worse (mesh IoU 0.42 against 0.44),
  // and the skeleton figures downstream move with the grid (README).
  int cauchy_every = 0;
  double tolerance = 1e-3;
  // Solver "cgls" only: each pass fixes the clamped voxels at zero and
  // re-solves for the rest (0 = clamp once, as the thesis).
  int nonnegative_passes = 0;
  // Voxels whose final opacity is below this are not stored (alpha).
  double min_output_opacity = 1e-3;
  // The density stage's warm start (the app's loop, issue 18): a run that is
  // not forced re-solves from the last solve's state (cache/) when only the
  // mattes or density edits changed, and stops as converged as that solve
  // was: 1-3 iterations instead of 50 after an edit, within 0.001 of the
  // cold solve's IoU. Off by default: the grid then depends (slightly) on
  // the run before, and sylva's promise is that the same inputs give the
  // same tree; a forced run always starts cold. Read by the density stage,
  // not by ReconstructDensity (which is given the state or not).
  bool warm_start = false;

  // Throws InputError naming the first violated constraint
  // ("Density.resolution must be ...").
  void Check() const;
};

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_
