// The reconstruct module's option checks (with density/density_options.cc
// and matting/matting_options.cc), apart from the algorithms so that reading
// and checking a project's options (ui/pipeline, fuzz/project_fuzzer.cc)
// does not link them.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <utility>

#include "core/util/check.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/matting/matte_set.h"
#include "reconstruct/measurement/branch_width.h"
#include "reconstruct/registration/colmap_runner.h"
#include "reconstruct/registration/loose_registration.h"
#include "reconstruct/registration/world_frame.h"

namespace sylva {
namespace {

// Throws InputError("<section>.<field>") unless `ok`.
void CheckRange(const char* section, bool ok, const char* field, const std::string& requirement,
                double value) {
  SYLVA_CHECK_INPUT(ok, std::string(section) + "." + field)
      << "must be " << requirement << ", got " << value;
}

}  // namespace

void MatteSetOptions::Check() const {
  SYLVA_CHECK_INPUT(static_min_photos >= 3, "MatteSet.static_min_photos")
      << "must be >= 3, got " << static_min_photos;
  SYLVA_CHECK_INPUT(static_photo_fraction > 0.5 && static_photo_fraction <= 1,
                    "MatteSet.static_photo_fraction")
      << "must be in (0.5, 1], got " << static_photo_fraction;
  SYLVA_CHECK_INPUT(static_color_tolerance > 0 && static_color_tolerance <= 1,
                    "MatteSet.static_color_tolerance")
      << "must be in (0, 1], got " << static_color_tolerance;
  SYLVA_CHECK_INPUT(static_margin_px >= 0 && static_margin_px <= 10, "MatteSet.static_margin_px")
      << "must be between 0 and 10 pixels, got " << static_margin_px;
  SYLVA_CHECK_INPUT(static_min_moving_share >= 0 && static_min_moving_share < 1,
                    "MatteSet.static_min_moving_share")
      << "must be in [0, 1), got " << static_min_moving_share;
  SYLVA_CHECK_INPUT(max_border_share > 0 && max_border_share <= 1, "MatteSet.max_border_share")
      << "must be in (0, 1], got " << max_border_share;
  SYLVA_CHECK_INPUT(max_foreground_ratio > 1, "MatteSet.max_foreground_ratio")
      << "must be > 1, got " << max_foreground_ratio;
  SYLVA_CHECK_INPUT(analysis_size >= 32 && analysis_size <= 16384, "MatteSet.analysis_size")
      << "must be between 32 and 16384 pixels, got " << analysis_size;
}

void ColmapOptions::Check() const {
  SYLVA_CHECK_INPUT(!executable.empty(), "Colmap.executable") << "must not be empty";
  SYLVA_CHECK_INPUT(matcher == "auto" || matcher == "exhaustive" || matcher == "sequential",
                    "Colmap.matcher")
      << "must be 'auto', 'exhaustive' or 'sequential', got '" << matcher << "'";
  SYLVA_CHECK_INPUT(exhaustive_max_photos >= 2, "Colmap.exhaustive_max_photos")
      << "must be >= 2, got " << exhaustive_max_photos;
  SYLVA_CHECK_INPUT(sequential_overlap >= 1, "Colmap.sequential_overlap")
      << "must be >= 1, got " << sequential_overlap;
  SYLVA_CHECK_INPUT(max_image_size >= 100 && max_image_size <= 20000, "Colmap.max_image_size")
      << "must be between 100 and 20000 pixels, got " << max_image_size;
  SYLVA_CHECK_INPUT(max_num_features >= 100, "Colmap.max_num_features")
      << "must be >= 100, got " << max_num_features;
  const bool known_model = camera_model == "SIMPLE_PINHOLE" || camera_model == "PINHOLE" ||
                           camera_model == "SIMPLE_RADIAL" || camera_model == "RADIAL" ||
                           camera_model == "OPENCV";
  SYLVA_CHECK_INPUT(known_model, "Colmap.camera_model")
      << "must be SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL or OPENCV, got '" << camera_model
      << "'";
  SYLVA_CHECK_INPUT(num_threads == -1 || num_threads >= 1, "Colmap.num_threads")
      << "must be -1 (all cores) or >= 1, got " << num_threads;
  SYLVA_CHECK_INPUT(mapper_attempts >= 1 && mapper_attempts <= 20, "Colmap.mapper_attempts")
      << "must be between 1 and 20, got " << mapper_attempts;
  SYLVA_CHECK_INPUT(random_seed >= 0, "Colmap.random_seed") << "must be >= 0, got " << random_seed;
  SYLVA_CHECK_INPUT(stall_seconds >= 0.0, "Colmap.stall_seconds")
      << "must be >= 0 (0 = never stop a silent COLMAP), got " << stall_seconds;
  SYLVA_CHECK_INPUT(rematch_below >= 0.0 && rematch_below <= 1.0, "Colmap.rematch_below")
      << "must be between 0 and 1, got " << rematch_below;
}

void WorldFrameOptions::Check() const {
  const bool axis =
      std::find(std::begin(kUpAxisNames), std::end(kUpAxisNames), up) != std::end(kUpAxisNames);
  SYLVA_CHECK_INPUT(up == "auto" || up == "keep" || axis, "WorldFrame.up")
      << "must be 'auto', 'keep' or an axis (+x, -x, +y, -y, +z, -z), got '" << up << "'";
  SYLVA_CHECK_INPUT(base == "auto" || base == "keep", "WorldFrame.base")
      << "must be 'auto' or 'keep', got '" << base << "'";
  SYLVA_CHECK_INPUT(std::isfinite(known_height) && known_height >= 0, "WorldFrame.known_height")
      << "must be >= 0 (0 = unknown), got " << known_height;
  SYLVA_CHECK_INPUT(!units.empty(), "WorldFrame.units") << "must not be empty";
  SYLVA_CHECK_INPUT(matte_threshold >= 0 && matte_threshold < 1, "WorldFrame.matte_threshold")
      << "must be in [0, 1), got " << matte_threshold;
  SYLVA_CHECK_INPUT(matte_working_size >= 16 && matte_working_size <= 8192,
                    "WorldFrame.matte_working_size")
      << "must be between 16 and 8192 pixels, got " << matte_working_size;
  SYLVA_CHECK_INPUT(min_part_fraction >= 0 && min_part_fraction <= 1,
                    "WorldFrame.min_part_fraction")
      << "must be in [0, 1], got " << min_part_fraction;
  SYLVA_CHECK_INPUT(band_fraction >= 0 && band_fraction < 1, "WorldFrame.band_fraction")
      << "must be in [0, 1), got " << band_fraction;
  SYLVA_CHECK_INPUT(consensus > 0 && consensus <= 1, "WorldFrame.consensus")
      << "must be in (0, 1], got " << consensus;
  SYLVA_CHECK_INPUT(ring_min_views >= 3, "WorldFrame.ring_min_views")
      << "must be >= 3, got " << ring_min_views;
  SYLVA_CHECK_INPUT(ring_max_thickness > 0 && ring_max_thickness <= 1,
                    "WorldFrame.ring_max_thickness")
      << "must be in (0, 1], got " << ring_max_thickness;
  SYLVA_CHECK_INPUT(ring_max_tilt_degrees >= 0 && ring_max_tilt_degrees <= 90,
                    "WorldFrame.ring_max_tilt_degrees")
      << "must be in [0, 90], got " << ring_max_tilt_degrees;
}

void LooseInitOptions::Check() const {
  CheckRange("LooseInit", assumed_tree_height > 0 && std::isfinite(assumed_tree_height),
             "assumed_tree_height", "> 0 world units", assumed_tree_height);
  CheckRange("LooseInit", default_focal_factor > 0 && std::isfinite(default_focal_factor),
             "default_focal_factor", "> 0", default_focal_factor);
  CheckRange("LooseInit", matte_threshold > 0 && matte_threshold < 1, "matte_threshold",
             "in (0, 1)", matte_threshold);
  CheckRange("LooseInit", min_row_fraction >= 0 && min_row_fraction < 1, "min_row_fraction",
             "in [0, 1)", min_row_fraction);
  CheckRange("LooseInit", base_band_fraction > 0 && base_band_fraction <= 1, "base_band_fraction",
             "in (0, 1]", base_band_fraction);
  CheckRange("LooseInit", fallback_fill > 0 && fallback_fill <= 1, "fallback_fill", "in (0, 1]",
             fallback_fill);
  CheckRange("LooseInit",
             orthographic_distance_heights > 0 && std::isfinite(orthographic_distance_heights),
             "orthographic_distance_heights", "> 0", orthographic_distance_heights);
}

void LooseRefineOptions::Check() const {
  CheckRange("LooseRefine", click_sigma_px > 0 && std::isfinite(click_sigma_px), "click_sigma_px",
             "> 0 pixels", click_sigma_px);
  CheckRange("LooseRefine", robust_loss_px > 0 && std::isfinite(robust_loss_px), "robust_loss_px",
             "> 0 pixels", robust_loss_px);
  CheckRange("LooseRefine", azimuth_sigma_deg > 0 && azimuth_sigma_deg <= 180, "azimuth_sigma_deg",
             "in (0, 180] degrees", azimuth_sigma_deg);
  CheckRange("LooseRefine", elevation_sigma_deg > 0 && elevation_sigma_deg <= 180,
             "elevation_sigma_deg", "in (0, 180] degrees", elevation_sigma_deg);
  CheckRange("LooseRefine", roll_sigma_deg > 0 && roll_sigma_deg <= 180, "roll_sigma_deg",
             "in (0, 180] degrees", roll_sigma_deg);
  CheckRange("LooseRefine", known_focal_sigma > 0 && std::isfinite(known_focal_sigma),
             "known_focal_sigma", "> 0", known_focal_sigma);
  CheckRange("LooseRefine", unknown_focal_sigma > 0 && std::isfinite(unknown_focal_sigma),
             "unknown_focal_sigma", "> 0", unknown_focal_sigma);
  CheckRange("LooseRefine", max_iterations >= 1 && max_iterations <= 100000, "max_iterations",
             "between 1 and 100000", max_iterations);
  CheckRange("LooseRefine", weak_direction_threshold > 0 && weak_direction_threshold < 1,
             "weak_direction_threshold", "in (0, 1)", weak_direction_threshold);
}

void LivewireOptions::Check() const {
  SYLVA_CHECK_INPUT(seeds == "farthest_point" || seeds == "skeleton_tips" || seeds == "silhouette",
                    "Attractors.seeds")
      << "must be \"farthest_point\", \"skeleton_tips\" or \"silhouette\", got \"" << seeds << "\"";
  SYLVA_CHECK_INPUT(num_seeds >= 1, "Attractors.num_seeds") << "must be >= 1, got " << num_seeds;
  SYLVA_CHECK_INPUT(max_image_size >= 16, "Attractors.max_image_size")
      << "must be >= 16 pixels, got " << max_image_size;
  SYLVA_CHECK_INPUT(matte_threshold > 0 && matte_threshold < 1, "Attractors.matte_threshold")
      << "must be in (0, 1), got " << matte_threshold;
  SYLVA_CHECK_INPUT(simplify_tolerance >= 0 && std::isfinite(simplify_tolerance),
                    "Attractors.simplify_tolerance")
      << "must be a finite number >= 0 pixels, got " << simplify_tolerance;
  for (const auto& [value, name] : {std::pair{weight_outside, "Attractors.weight_outside"},
                                    std::pair{weight_direction, "Attractors.weight_direction"},
                                    std::pair{weight_centerline, "Attractors.weight_centerline"}}) {
    SYLVA_CHECK_INPUT(value >= 0 && std::isfinite(value), name) << "must be >= 0, got " << value;
  }
  SYLVA_CHECK_INPUT(weight_outside + weight_direction + weight_centerline > 1e-6,
                    "Attractors.weight_outside")
      << "the three livewire weights must not all be zero";
  SYLVA_CHECK_INPUT(min_twig_length >= 0 && min_twig_length < 1, "Attractors.min_twig_length")
      << "must be in [0, 1), got " << min_twig_length;
  SYLVA_CHECK_INPUT(photo_weight >= 0 && photo_weight <= 1, "Attractors.photo_weight")
      << "must be in [0, 1], got " << photo_weight;
  SYLVA_CHECK_INPUT(snap_radius >= 0 && std::isfinite(snap_radius), "Attractors.snap_radius")
      << "must be a finite number >= 0 pixels, got " << snap_radius;
}

void BranchWidthOptions::Check() const {
  SYLVA_CHECK_INPUT(mode == "auto" || mode == "on" || mode == "off", "BranchWidth.mode")
      << "must be auto, on or off, got '" << mode << "'";
  SYLVA_CHECK_INPUT(matte_threshold > 0 && matte_threshold <= 1, "BranchWidth.matte_threshold")
      << "must be in (0, 1], got " << matte_threshold;
  SYLVA_CHECK_INPUT(view_quantile >= 0 && view_quantile <= 1, "BranchWidth.view_quantile")
      << "must be in [0, 1], got " << view_quantile;
  SYLVA_CHECK_INPUT(min_views >= 1, "BranchWidth.min_views") << "must be >= 1, got " << min_views;
  SYLVA_CHECK_INPUT(min_side_on > 0 && min_side_on <= 1, "BranchWidth.min_side_on")
      << "must be in (0, 1], got " << min_side_on;
  SYLVA_CHECK_INPUT(search_pixels >= 0 && search_pixels <= 50, "BranchWidth.search_pixels")
      << "must be in [0, 50], got " << search_pixels;
  SYLVA_CHECK_INPUT(min_measured_share >= 0 && min_measured_share <= 1,
                    "BranchWidth.min_measured_share")
      << "must be in [0, 1], got " << min_measured_share;
}

}  // namespace sylva
