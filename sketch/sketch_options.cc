// The sketch module's option checks and option-value names, apart from the
// algorithms so that reading and checking a project's options (ui/pipeline,
// fuzz/project_fuzzer.cc) does not link them.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>

#include "core/util/check.h"
#include "sketch/branch_mrf.h"
#include "sketch/concept_plant.h"
#include "sketch/concept_sketch.h"
#include "sketch/gesture_options.h"
#include "sketch/silhouette_tree.h"
#include "sketch/sketch_views.h"
#include "sketch/stroke_graph.h"

namespace sylva {
namespace {

constexpr ConceptPattern kPatterns[] = {ConceptPattern::kSpiral, ConceptPattern::kMonostichous,
                                        ConceptPattern::kDistichous, ConceptPattern::kTristichous,
                                        ConceptPattern::kTetrastichous};

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

const char* ConceptPatternName(ConceptPattern pattern) {
  switch (pattern) {
    case ConceptPattern::kSpiral:
      return "spiral";
    case ConceptPattern::kMonostichous:
      return "monostichous";
    case ConceptPattern::kDistichous:
      return "distichous";
    case ConceptPattern::kTristichous:
      return "tristichous";
    case ConceptPattern::kTetrastichous:
      return "tetrastichous";
  }
  return "spiral";
}

std::optional<ConceptPattern> ConceptPatternFromName(const std::string& name) {
  const std::string lower = Lower(name);
  for (ConceptPattern pattern : kPatterns) {
    if (lower == ConceptPatternName(pattern)) return pattern;
  }
  return std::nullopt;
}

void StrokeGraphOptions::Check() const {
  SYLVA_CHECK_INPUT(std::isfinite(snap_distance) && snap_distance >= 0,
                    "Attractors.stroke_snap_distance")
      << "must be a finite distance >= 0 in pixels, got " << snap_distance;
  SYLVA_CHECK_INPUT(std::isfinite(simplify_tolerance) && simplify_tolerance >= 0,
                    "Attractors.stroke_simplify_tolerance")
      << "must be a finite distance >= 0 in pixels, got " << simplify_tolerance;
  SYLVA_CHECK_INPUT(resample_spacing > 0, "Attractors.stroke_resample_spacing")
      << "must be > 0 pixels (infinity: no resampling), got " << resample_spacing;
}

void SketchViewOptions::Check() const {
  SYLVA_CHECK_INPUT(image_size >= 32 && image_size <= 8192, "Sketch.image_size")
      << "must be in [32, 8192] pixels, got " << image_size;
  SYLVA_CHECK_INPUT(std::isfinite(tree_height) && tree_height > 0, "Sketch.tree_height")
      << "must be > 0, got " << tree_height;
  SYLVA_CHECK_INPUT(crown_opacity > 0 && crown_opacity < 1, "Sketch.crown_opacity")
      << "must be in (0, 1), got " << crown_opacity;
  SYLVA_CHECK_INPUT(line_width > 0 && line_width < 0.1, "Sketch.line_width")
      << "must be in (0, 0.1), got " << line_width;
  SYLVA_CHECK_INPUT(gap_closing >= 0 && gap_closing < 0.2, "Sketch.gap_closing")
      << "must be in [0, 0.2), got " << gap_closing;
  SYLVA_CHECK_INPUT(valley_depth > 0 && valley_depth < 0.5, "Sketch.valley_depth")
      << "must be in (0, 0.5), got " << valley_depth;
  SYLVA_CHECK_INPUT(branch_reach > 0 && branch_reach <= 1, "Sketch.branch_reach")
      << "must be in (0, 1], got " << branch_reach;
}

void ConceptPlantOptions::Check() const {
  SYLVA_CHECK_INPUT(phyllotaxis == "auto" || ConceptPatternFromName(phyllotaxis).has_value(),
                    "Concept.phyllotaxis")
      << "expected auto, spiral, monostichous, distichous, tristichous or tetrastichous, got '"
      << phyllotaxis << "'";
  SYLVA_CHECK_INPUT(std::isfinite(divergence_deg) && divergence_deg < 360, "Concept.divergence_deg")
      << "must be < 360 (< 0 for the pattern's), got " << divergence_deg;
  SYLVA_CHECK_INPUT(organs_per_layer >= 1 && organs_per_layer <= 1000, "Concept.organs_per_layer")
      << "must be in [1, 1000], got " << organs_per_layer;
  SYLVA_CHECK_INPUT(organs_per_node >= 1 && organs_per_node <= 8, "Concept.organs_per_node")
      << "must be in [1, 8], got " << organs_per_node;
  SYLVA_CHECK_INPUT(std::isfinite(first_azimuth_deg), "Concept.first_azimuth_deg")
      << "must be finite";
  SYLVA_CHECK_INPUT(default_branching_deg > 0 && default_branching_deg < 180,
                    "Concept.default_branching_deg")
      << "must be in (0, 180), got " << default_branching_deg;
  SYLVA_CHECK_INPUT(stem_length > 0 && std::isfinite(stem_length), "Concept.stem_length")
      << "must be > 0, got " << stem_length;
  SYLVA_CHECK_INPUT(stem_radius_fraction > 0 && stem_radius_fraction <= 0.2,
                    "Concept.stem_radius_fraction")
      << "must be in (0, 0.2], got " << stem_radius_fraction;
  SYLVA_CHECK_INPUT(stem_tip_fraction > 0 && stem_tip_fraction <= 1, "Concept.stem_tip_fraction")
      << "must be in (0, 1], got " << stem_tip_fraction;
  SYLVA_CHECK_INPUT(organ_droop >= -1 && organ_droop <= 1, "Concept.organ_droop")
      << "must be in [-1, 1], got " << organ_droop;
  SYLVA_CHECK_INPUT(organ_fold_deg >= 0 && organ_fold_deg <= 60, "Concept.organ_fold_deg")
      << "must be in [0, 60], got " << organ_fold_deg;
  SYLVA_CHECK_INPUT(organ_axis_radius_fraction > 0 && organ_axis_radius_fraction <= 0.2,
                    "Concept.organ_axis_radius_fraction")
      << "must be in (0, 0.2], got " << organ_axis_radius_fraction;
}

void GestureTreeOptions::Check() const {
  SYLVA_CHECK_INPUT(iterations >= 0 && iterations <= 30, "Gesture.iterations")
      << "must be in [0, 30], got " << iterations;
  SYLVA_CHECK_INPUT(trunk_segments >= 2, "Gesture.trunk_segments") << "must be >= 2";
  SYLVA_CHECK_INPUT(smoothing_passes >= 0, "Gesture.smoothing_passes") << "must be >= 0";
  SYLVA_CHECK_INPUT(trunk_radius > 0, "Gesture.trunk_radius") << "must be > 0";
  SYLVA_CHECK_INPUT(max_speed_ratio >= 1, "Gesture.max_speed_ratio") << "must be >= 1";
  SYLVA_CHECK_INPUT(crown_base >= 0 && crown_base <= 1, "Gesture.crown_base")
      << "must be in [0, 1]";
  SYLVA_CHECK_INPUT(growth_spacing > 0 && growth_spacing <= 1, "Gesture.growth_spacing")
      << "must be in (0, 1]";
  SYLVA_CHECK_INPUT(branch_length > 0, "Gesture.branch_length") << "must be > 0";
  SYLVA_CHECK_INPUT(branch_radius_ratio > 0, "Gesture.branch_radius_ratio") << "must be > 0";
  SYLVA_CHECK_INPUT(roi_e > 0 && roi_e <= 4, "Gesture.roi_e") << "must be in (0, 4]";
  SYLVA_CHECK_INPUT(roi_n <= 4, "Gesture.roi_n") << "must be <= 4 (<= 0: fitted)";
  SYLVA_CHECK_INPUT(roi_alpha >= 0, "Gesture.roi_alpha") << "must be >= 0";
  SYLVA_CHECK_INPUT(roi_min_width > 0, "Gesture.roi_min_width") << "must be > 0";
  SYLVA_CHECK_INPUT(roi_margin > 0.5, "Gesture.roi_margin") << "must be > 0.5";
  SYLVA_CHECK_INPUT(roi_lift >= 0, "Gesture.roi_lift") << "must be >= 0";
  SYLVA_CHECK_INPUT(avoid_turns >= 0 && avoid_turn_deg > 0, "Gesture.avoid_turns")
      << "needs avoid_turns >= 0 and Gesture.avoid_turn_deg > 0";
  SYLVA_CHECK_INPUT(min_segment_fraction > 0 && min_segment_fraction < 1,
                    "Gesture.min_segment_fraction")
      << "must be in (0, 1)";
}

void MrfOptions::Check() const {
  SYLVA_CHECK_INPUT(interaction >= 0 && std::isfinite(interaction), "Sketch.mrf_interaction")
      << "must be >= 0, got " << interaction;
  SYLVA_CHECK_INPUT(density_grid >= 2 && density_grid <= 256, "Sketch.mrf_grid")
      << "must be in [2, 256], got " << density_grid;
  SYLVA_CHECK_INPUT(crowding_reach >= 0, "Sketch.mrf_reach")
      << "must be >= 0, got " << crowding_reach;
  SYLVA_CHECK_INPUT(depth_candidates >= 3, "Sketch.mrf_candidates")
      << "must be >= 3, got " << depth_candidates;
  SYLVA_CHECK_INPUT(max_icm_sweeps >= 0, "Sketch.mrf_sweeps") << "must be >= 0";
  SYLVA_CHECK_INPUT(icm_epsilon > 0, "Sketch.mrf_epsilon") << "must be > 0";
  SYLVA_CHECK_INPUT(em_iterations >= 0, "Sketch.mrf_em_iterations") << "must be >= 0";
  SYLVA_CHECK_INPUT(prior_weight >= 0, "Sketch.mrf_prior_weight") << "must be >= 0";
  SYLVA_CHECK_INPUT(generations >= 0 && generations <= 20, "Sketch.generations")
      << "must be in [0, 20], got " << generations;
  SYLVA_CHECK_INPUT(max_segments >= 1, "Sketch.max_segments") << "must be >= 1";
}

void SilhouetteTreeOptions::Check() const {
  SYLVA_CHECK_INPUT(baf_base_deg >= 0 && baf_base_deg <= 180, "Sketch.silhouette_baf_base_deg")
      << "must be in [0, 180] degrees, got " << baf_base_deg;
  SYLVA_CHECK_INPUT(baf_tip_deg >= 0 && baf_tip_deg <= 180, "Sketch.silhouette_baf_tip_deg")
      << "must be in [0, 180] degrees, got " << baf_tip_deg;
  SYLVA_CHECK_INPUT(valley_depth > 0 && valley_depth < 1, "Sketch.silhouette_valley_depth")
      << "must be in (0, 1), got " << valley_depth;
  SYLVA_CHECK_INPUT(cone_min_deg > 0 && cone_min_deg <= cone_max_deg && cone_max_deg < 180,
                    "Sketch.silhouette_cone_min_deg")
      << "needs 0 < cone_min_deg <= cone_max_deg < 180, got " << cone_min_deg << " and "
      << cone_max_deg;
  SYLVA_CHECK_INPUT(levels >= 1 && levels <= 6, "Sketch.silhouette_levels")
      << "must be in [1, 6], got " << levels;
  SYLVA_CHECK_INPUT(max_overlap >= 0 && max_overlap <= 1, "Sketch.silhouette_max_overlap")
      << "must be in [0, 1], got " << max_overlap;
  SYLVA_CHECK_INPUT(extra_branches >= 0 && extra_branches <= 4, "Sketch.silhouette_extra_branches")
      << "must be in [0, 4], got " << extra_branches;
  SYLVA_CHECK_INPUT(phyllotaxis == "none" || phyllotaxis == "spiral" ||
                        phyllotaxis == "decussate" || phyllotaxis == "whorl3",
                    "Sketch.silhouette_phyllotaxis")
      << "must be none, spiral, decussate or whorl3, got '" << phyllotaxis << "'";
  SYLVA_CHECK_INPUT(drawn_spread_deg >= 0 && drawn_spread_deg <= 180,
                    "Sketch.silhouette_drawn_spread_deg")
      << "must be in [0, 180] degrees, got " << drawn_spread_deg;
  SYLVA_CHECK_INPUT(gibbs_alpha > 0, "Sketch.silhouette_gibbs_alpha")
      << "must be positive, got " << gibbs_alpha;
  SYLVA_CHECK_INPUT(gibbs_iterations >= 0 && gibbs_iterations <= 1000000,
                    "Sketch.silhouette_gibbs_iterations")
      << "must be in [0, 10^6], got " << gibbs_iterations;
  SYLVA_CHECK_INPUT(max_branches >= 2 && max_branches <= 1000000, "Sketch.silhouette_max_branches")
      << "must be in [2, 10^6], got " << max_branches;
  SYLVA_CHECK_INPUT(min_branch_share > 0 && min_branch_share < 1,
                    "Sketch.silhouette_min_branch_share")
      << "must be in (0, 1), got " << min_branch_share;
}

}  // namespace sylva
