#include "reconstruct/density/density_options.h"

#include "core/util/check.h"

namespace sylva {

void DensityOptions::Check() const {
  SYLVA_CHECK_INPUT(resolution >= 4 && resolution <= 2048, "Density.resolution")
      << "must be between 4 and 2048 voxels, got " << resolution;
  SYLVA_CHECK_INPUT(max_resolution >= 0 && max_resolution <= 2048, "Density.max_resolution")
      << "must be between 0 and 2048 voxels, got " << max_resolution;
  SYLVA_CHECK_INPUT(max_thin_share > 0 && max_thin_share <= 1, "Density.max_thin_share")
      << "must be in (0, 1], got " << max_thin_share;
  SYLVA_CHECK_INPUT(bounds.isEmpty() || (bounds.sizes().array() > 0).all(), "Density.bounds")
      << "must have positive size on every axis";
  SYLVA_CHECK_INPUT(bounds_margin_voxels >= 0, "Density.bounds_margin_voxels")
      << "must be >= 0, got " << bounds_margin_voxels;
  SYLVA_CHECK_INPUT(hull_resolution >= 4 && hull_resolution <= 1024, "Density.hull_resolution")
      << "must be between 4 and 1024 voxels, got " << hull_resolution;
  SYLVA_CHECK_INPUT(hull_alpha_threshold >= 0 && hull_alpha_threshold < 1,
                    "Density.hull_alpha_threshold")
      << "must be in [0, 1), got " << hull_alpha_threshold;
  SYLVA_CHECK_INPUT(view_outlier_fraction >= 0 && view_outlier_fraction < 0.5,
                    "Density.view_outlier_fraction")
      << "must be in [0, 0.5), got " << view_outlier_fraction;
  SYLVA_CHECK_INPUT(view_consensus_min_views >= 3, "Density.view_consensus_min_views")
      << "must be >= 3, got " << view_consensus_min_views;
  SYLVA_CHECK_INPUT(view_max_carved_share > 0 && view_max_carved_share <= 1,
                    "Density.view_max_carved_share")
      << "must be in (0, 1], got " << view_max_carved_share;
  SYLVA_CHECK_INPUT(view_carved_share_ratio > 1, "Density.view_carved_share_ratio")
      << "must be > 1, got " << view_carved_share_ratio;
  SYLVA_CHECK_INPUT(carve_threshold >= 0 && carve_threshold < 1, "Density.carve_threshold")
      << "must be in [0, 1), got " << carve_threshold;
  SYLVA_CHECK_INPUT(carve_dissent >= 0 && carve_dissent < 0.5, "Density.carve_dissent")
      << "must be in [0, 0.5), got " << carve_dissent;
  SYLVA_CHECK_INPUT(carve_min_views >= 1, "Density.carve_min_views")
      << "must be at least 1, got " << carve_min_views;
  SYLVA_CHECK_INPUT(pixels_per_voxel > 0 && pixels_per_voxel <= 64, "Density.pixels_per_voxel")
      << "must be in (0, 64], got " << pixels_per_voxel;
  SYLVA_CHECK_INPUT(rays_per_axis >= 1 && rays_per_axis <= 8, "Density.rays_per_axis")
      << "must be between 1 and 8, got " << rays_per_axis;
  SYLVA_CHECK_INPUT(max_pixel_opacity > 0 && max_pixel_opacity < 1, "Density.max_pixel_opacity")
      << "must be in (0, 1), got " << max_pixel_opacity;
  SYLVA_CHECK_INPUT(min_row_weight > 0 && min_row_weight <= 1, "Density.min_row_weight")
      << "must be in (0, 1], got " << min_row_weight;
  SYLVA_CHECK_INPUT(solver == "projected" || solver == "cgls", "Density.solver")
      << "must be 'projected' or 'cgls', got '" << solver << "'";
  SYLVA_CHECK_INPUT(max_iterations >= 0 && max_iterations <= 100000, "Density.max_iterations")
      << "must be between 0 and 100000, got " << max_iterations;
  SYLVA_CHECK_INPUT(cauchy_every >= 0 && cauchy_every <= 1000, "Density.cauchy_every")
      << "must be between 0 and 1000, got " << cauchy_every;
  SYLVA_CHECK_INPUT(tolerance >= 0 && tolerance < 1, "Density.tolerance")
      << "must be in [0, 1), got " << tolerance;
  SYLVA_CHECK_INPUT(nonnegative_passes >= 0 && nonnegative_passes <= 100,
                    "Density.nonnegative_passes")
      << "must be between 0 and 100, got " << nonnegative_passes;
  SYLVA_CHECK_INPUT(min_output_opacity >= 0 && min_output_opacity < 1, "Density.min_output_opacity")
      << "must be in [0, 1), got " << min_output_opacity;
}

}  // namespace sylva
