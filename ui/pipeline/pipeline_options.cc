#include "ui/pipeline/pipeline_options.h"

#include "core/util/check.h"

namespace sylva {

void GeneralOptions::Check() const {
  SYLVA_CHECK_INPUT(num_threads >= 0 && num_threads <= 1024, "General.num_threads")
      << "must be between 0 (all cores) and 1024, got " << num_threads;
}

void ReportOptions::Check() const {
  SYLVA_CHECK_INPUT(opacity_threshold > 0 && opacity_threshold < 1, "Report.opacity_threshold")
      << "must be in (0, 1), got " << opacity_threshold;
  SYLVA_CHECK_INPUT(matte_threshold > 0 && matte_threshold <= 1, "Report.matte_threshold")
      << "must be in (0, 1], got " << matte_threshold;
  SYLVA_CHECK_INPUT(pixels_per_voxel > 0 && pixels_per_voxel <= 64, "Report.pixels_per_voxel")
      << "must be in (0, 64], got " << pixels_per_voxel;
}

void PipelineOptions::Check() const {
  general.Check();
  density.Check();
  report.Check();
}

namespace {

void RegisterGeneral(GeneralOptions* o, OptionRegistry* r) {
  r->AddUint64("General.seed", &o->seed, "", "seed of every random choice; same seed, same tree");
  r->AddInt("General.num_threads", &o->num_threads, "threads", "worker threads; 0 = all cores");
}

void RegisterDensity(DensityOptions* o, OptionRegistry* r) {
  r->AddInt("Density.resolution", &o->resolution, "voxels",
            "voxels along the longest side of the bounds");
  r->AddBox("Density.bounds", &o->bounds, "world units",
            "grid bounds x0,y0,z0,x1,y1,z1, or auto (visual hull of the mattes)");
  r->AddDouble("Density.bounds_margin_voxels", &o->bounds_margin_voxels, "voxels",
               "margin around automatic bounds");
  r->AddInt("Density.hull_resolution", &o->hull_resolution, "voxels",
            "coarse carving grid that finds automatic bounds (longest side)");
  r->AddDouble("Density.hull_alpha_threshold", &o->hull_alpha_threshold, "alpha",
               "matte value above which a pixel is foreground for the visual hull");
  r->AddDouble("Density.carve_threshold", &o->carve_threshold, "alpha",
               "voxels whose initial opacity (min over views of the mean matte over the "
               "footprint) is below this are carved (thesis 3.3)");
  r->AddDouble("Density.pixels_per_voxel", &o->pixels_per_voxel, "pixels",
               "images are downsampled so a voxel covers about this many pixels across");
  r->AddInt("Density.rays_per_axis", &o->rays_per_axis, "rays",
            "rays per downsampled pixel along each axis (n x n)");
  r->AddDouble("Density.max_pixel_opacity", &o->max_pixel_opacity, "alpha",
               "matte values are clamped to this before -log(1 - alpha)");
  r->AddDouble("Density.min_row_weight", &o->min_row_weight, "",
               "pixel equations weighted by max(1 - alpha, this): fits opacity rather than "
               "depth; 1 = unweighted (thesis)");
  r->AddString("Density.solver", &o->solver,
               "projected (non-negative least squares) or cgls (thesis: least squares, then "
               "negatives clamped)");
  r->AddInt("Density.max_iterations", &o->max_iterations, "iterations",
            "iterations per least-squares solve");
  r->AddDouble("Density.tolerance", &o->tolerance, "relative",
               "stop when the (projected) gradient falls below tolerance times its start");
  r->AddInt("Density.nonnegative_passes", &o->nonnegative_passes, "passes",
            "cgls only: re-solves with clamped voxels fixed at zero (0 = clamp once, as the "
            "thesis)");
  r->AddDouble("Density.min_output_opacity", &o->min_output_opacity, "alpha",
               "voxels below this opacity are not stored");
}

void RegisterReport(ReportOptions* o, OptionRegistry* r) {
  r->AddDouble("Report.opacity_threshold", &o->opacity_threshold, "alpha",
               "projected density at or above this is foreground");
  r->AddDouble("Report.matte_threshold", &o->matte_threshold, "alpha",
               "matte at or above this is foreground");
  r->AddDouble("Report.pixels_per_voxel", &o->pixels_per_voxel, "pixels",
               "comparison resolution: images downsampled so a voxel covers about this many "
               "pixels");
  r->AddBool("Report.write_images", &o->write_images,
             "write per-view comparison pictures and report.html");
}

}  // namespace

void RegisterPipelineOptions(PipelineOptions* options, OptionRegistry* registry) {
  RegisterGeneral(&options->general, registry);
  RegisterDensity(&options->density, registry);
  RegisterReport(&options->report, registry);
}

}  // namespace sylva
