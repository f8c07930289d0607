// Options of the density stage (thesis 3.3): back-projection of mattes into a
// voxel grid and least squares on per-pixel log-transparency.
#ifndef SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_
#define SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_

#include "core/geometry/box.h"

namespace sylva {

struct DensityOptions {
  // Voxels along the longest side of the reconstruction bounds. The thesis
  // used ~25; finer grids follow thin crowns better at a cubic memory cost.
  int resolution = 128;

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

  // Implicit carving (thesis 3.3): a voxel's initial opacity is the minimum
  // over views of the mean matte value over its footprint; voxels below this
  // opacity are dropped from the solve (alpha, unitless).
  double carve_threshold = 0.02;

  // Images are box-downsampled by an integer factor so that one voxel covers
  // about this many pixels (across) at the grid centre; keeps the system
  // about as large as the grid.
  double pixels_per_voxel = 1.0;
  // Rays per downsampled pixel along each axis (n x n rays, averaged).
  int rays_per_axis = 1;
  // Matte opacities are clamped to this before -log(1 - alpha): a fully
  // opaque pixel would need an infinite optical depth (alpha, < 1).
  double max_pixel_opacity = 0.98;

  // CGLS iterations per solve, and the stopping tolerance on
  // |A^T r| / |A^T b| (relative normal-equation residual).
  int max_iterations = 40;
  double tolerance = 1e-3;
  // The thesis clamps negative solutions to empty once (0 passes). Each pass
  // fixes the clamped voxels at zero and re-solves for the rest.
  int nonnegative_passes = 2;
  // Voxels whose final opacity is below this are not stored (alpha).
  double min_output_opacity = 1e-3;

  // Throws InputError naming the first violated constraint
  // ("Density.resolution must be ...").
  void Check() const;
};

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_DENSITY_OPTIONS_H_
