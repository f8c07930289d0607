// The mesh module's option checks and option-value parsers, apart from the
// meshers so that reading and checking a project's options (ui/pipeline,
// fuzz/project_fuzzer.cc) does not link the meshers.
#include <algorithm>
#include <cmath>

#include "core/util/check.h"
#include "mesh/allometry.h"
#include "mesh/bark_mesh.h"
#include "mesh/branch_mesh.h"
#include "mesh/leaves.h"
#include "mesh/pen_and_ink.h"
#include "mesh/phyllotaxis.h"
#include "mesh/tree_metrics.h"
#include "mesh/twigs.h"

namespace sylva {

void CheckBuiltinLeafShapeName(const std::string& name) {
  SYLVA_CHECK_INPUT(name == "quad" || name == "ovate" || name == "lanceolate" || name == "needle",
                    "Leaves.shape")
      << "unknown leaf shape \"" << name << "\" (quad, ovate, lanceolate, needle)";
}

void AllometryOptions::Check() const {
  SYLVA_CHECK_INPUT(diameter_exponent >= 1 && diameter_exponent <= 4, "Allometry.diameter_exponent")
      << "must be in [1, 4], got " << diameter_exponent;
  SYLVA_CHECK_INPUT(trunk_radius > 0 && std::isfinite(trunk_radius), "Allometry.trunk_radius")
      << "must be a positive length, got " << trunk_radius;
  SYLVA_CHECK_INPUT(min_radius >= 0 && min_radius <= trunk_radius, "Allometry.min_radius")
      << "must be in [0, trunk_radius = " << trunk_radius << "], got " << min_radius;
}

void BranchMeshOptions::Check() const {
  SYLVA_CHECK_INPUT(rings_per_segment >= 1 && rings_per_segment <= kMaxBranchRingsPerSegment,
                    "BranchMesh.rings_per_segment")
      << "must be in [1, " << kMaxBranchRingsPerSegment << "], got " << rings_per_segment;
  SYLVA_CHECK_INPUT(rings_per_unit_length >= 0 && std::isfinite(rings_per_unit_length),
                    "BranchMesh.rings_per_unit_length")
      << "must be >= 0, got " << rings_per_unit_length;
  SYLVA_CHECK_INPUT(min_sides >= 3 && min_sides <= max_sides, "BranchMesh.min_sides")
      << "must be in [3, max_sides = " << max_sides << "], got " << min_sides;
  SYLVA_CHECK_INPUT(max_sides <= kMaxBranchSides, "BranchMesh.max_sides")
      << "must be at most " << kMaxBranchSides << ", got " << max_sides;
  SYLVA_CHECK_INPUT(!bark.name.empty(), "BranchMesh.bark") << "the material needs a name";
  SYLVA_CHECK_INPUT(bark.diffuse_color.allFinite() && bark.diffuse_color.minCoeff() >= 0 &&
                        bark.diffuse_color.maxCoeff() <= 1,
                    "BranchMesh.bark")
      << "diffuse colour must be linear RGB in [0, 1]";
}

void BarkMeshOptions::Check() const {
  tube.Check();
  SYLVA_CHECK_INPUT(sphere_margin > 0 && sphere_margin <= 10, "BranchMesh.sphere_margin")
      << "must be in (0, 10], got " << sphere_margin;
  SYLVA_CHECK_INPUT(max_cut_fraction > 0 && max_cut_fraction < 1, "BranchMesh.max_cut_fraction")
      << "must be in (0, 1), got " << max_cut_fraction;
  SYLVA_CHECK_INPUT(min_radius_fraction > 0 && min_radius_fraction < 1,
                    "BranchMesh.min_radius_fraction")
      << "must be in (0, 1), got " << min_radius_fraction;
  SYLVA_CHECK_INPUT(attach_ratio >= 0 && attach_ratio <= 1, "BranchMesh.attach_ratio")
      << "must be in [0, 1], got " << attach_ratio;
  SYLVA_CHECK_INPUT(repair_rounds >= 0 && repair_rounds <= 16, "BranchMesh.repair_rounds")
      << "must be in [0, 16], got " << repair_rounds;
}

void TwigOptions::Check() const {
  SYLVA_CHECK_INPUT(pattern == "monopodial" || pattern == "sympodial", "Twigs.pattern")
      << "must be \"monopodial\" or \"sympodial\", got \"" << pattern << "\"";
  SYLVA_CHECK_INPUT(twigs_per_length >= 0 && twigs_per_length <= 1000, "Twigs.twigs_per_length")
      << "must be in [0, 1000] twigs per twig length, got " << twigs_per_length;
  SYLVA_CHECK_INPUT(max_density_factor >= 1, "Twigs.max_density_factor")
      << "must be >= 1, got " << max_density_factor;
  SYLVA_CHECK_INPUT(length >= 0, "Twigs.length") << "must be >= 0 world units, got " << length;
  SYLVA_CHECK_INPUT(length_fraction > 0 && length_fraction < 1, "Twigs.length_fraction")
      << "must be in (0, 1), got " << length_fraction;
  SYLVA_CHECK_INPUT(length_variation >= 0 && length_variation < 1, "Twigs.length_variation")
      << "must be in [0, 1), got " << length_variation;
  SYLVA_CHECK_INPUT(branching_angle_deg > 0 && branching_angle_deg < 180,
                    "Twigs.branching_angle_deg")
      << "must be in (0, 180) degrees, got " << branching_angle_deg;
  SYLVA_CHECK_INPUT(strand_fraction > 0 && strand_fraction <= 1, "Twigs.strand_fraction")
      << "must be in (0, 1], got " << strand_fraction;
  SYLVA_CHECK_INPUT(diameter_exponent >= 1 && diameter_exponent <= 4, "Twigs.diameter_exponent")
      << "must be in [1, 4], got " << diameter_exponent;
  SYLVA_CHECK_INPUT(tip_taper > 0 && tip_taper <= 1, "Twigs.tip_taper")
      << "must be in (0, 1], got " << tip_taper;
  SYLVA_CHECK_INPUT(tropism >= -1 && tropism <= 1, "Twigs.tropism")
      << "must be in [-1, 1], got " << tropism;
  SYLVA_CHECK_INPUT(stiffness >= 0 && stiffness <= 1, "Twigs.stiffness")
      << "must be in [0, 1], got " << stiffness;
  SYLVA_CHECK_INPUT(segments >= 1 && segments <= 64, "Twigs.segments")
      << "must be between 1 and 64, got " << segments;
  SYLVA_CHECK_INPUT(laterals >= 0 && laterals <= 16, "Twigs.laterals")
      << "must be between 0 and 16, got " << laterals;
  SYLVA_CHECK_INPUT(sympodial_angle_deg >= 0 && sympodial_angle_deg < 90,
                    "Twigs.sympodial_angle_deg")
      << "must be in [0, 90) degrees, got " << sympodial_angle_deg;
}

void TwigMeshOptions::Check() const {
  SYLVA_CHECK_INPUT(mode == "joined" || mode == "separate" || mode == "auto", "Twigs.mesh")
      << "must be joined, separate or auto, got \"" << mode << "\"";
  SYLVA_CHECK_INPUT(separate_above >= 0, "Twigs.separate_above")
      << "must be >= 0 twigs, got " << separate_above;
  SYLVA_CHECK_INPUT(!material.name.empty(), "Twigs.material") << "the material needs a name";
}

void LeafOptions::Check() const {
  SYLVA_CHECK_INPUT(num_leaves >= -1 && num_leaves <= 10000000, "Leaves.num_leaves")
      << "must be -1 (no leaves), 0 (from the leaf area) or up to 10^7, got " << num_leaves;
  SYLVA_CHECK_INPUT(max_leaves >= 1 && max_leaves <= 10000000, "Leaves.max_leaves")
      << "must be between 1 and 10^7, got " << max_leaves;
  SYLVA_CHECK_INPUT(max_draws_factor >= 1, "Leaves.max_draws_factor")
      << "must be >= 1, got " << max_draws_factor;
  SYLVA_CHECK_INPUT(leaf_length >= 0, "Leaves.leaf_length") << "must be >= 0, got " << leaf_length;
  SYLVA_CHECK_INPUT(leaf_length_fraction > 0 && leaf_length_fraction < 1,
                    "Leaves.leaf_length_fraction")
      << "must be in (0, 1), got " << leaf_length_fraction;
  SYLVA_CHECK_INPUT(leaf_aspect > 0 && leaf_aspect <= 10, "Leaves.leaf_aspect")
      << "must be in (0, 10], got " << leaf_aspect;
  SYLVA_CHECK_INPUT(twig_reach > 0, "Leaves.twig_reach") << "must be > 0, got " << twig_reach;
  SYLVA_CHECK_INPUT(thin_branch_radius_fraction > 0 && thin_branch_radius_fraction <= 1,
                    "Leaves.thin_branch_radius_fraction")
      << "must be in (0, 1], got " << thin_branch_radius_fraction;
  SYLVA_CHECK_INPUT(phototropism >= 0 && phototropism <= 1, "Leaves.phototropism")
      << "must be in [0, 1], got " << phototropism;
  SYLVA_CHECK_INPUT(matte_threshold >= 0 && matte_threshold < 1, "Leaves.matte_threshold")
      << "must be in [0, 1), got " << matte_threshold;
  CheckBuiltinLeafShapeName(shape);
  // Also used without phyllotaxis by GenerateSkeletonLeafInstances.
  SYLVA_CHECK_INPUT(internode > 0 && std::isfinite(internode), "Leaves.internode")
      << "must be > 0 leaf lengths, got " << internode;
  SYLVA_CHECK_INPUT(insertion_deg > 0 && insertion_deg < 180, "Leaves.insertion_deg")
      << "must be in (0, 180) degrees, got " << insertion_deg;
  if (phyllotaxis != "none") {
    PhyllotaxisOptions phyllo;
    phyllo.pattern = ParsePhyllotaxisPattern(phyllotaxis, "Leaves.phyllotaxis");
    SYLVA_CHECK_INPUT(divergence_deg >= -360 && divergence_deg <= 360, "Leaves.divergence_deg")
        << "must be in [-360, 360] degrees, got " << divergence_deg;
    SYLVA_CHECK_INPUT(leaves_per_whorl >= 3 && leaves_per_whorl <= 32, "Leaves.leaves_per_whorl")
        << "must be between 3 and 32, got " << leaves_per_whorl;
  }
}

PhyllotaxisPattern ParsePhyllotaxisPattern(const std::string& name, const std::string& option) {
  if (name == "alternate" || name == "distichous") return PhyllotaxisPattern::kAlternate;
  if (name == "opposite_decussate" || name == "decussate") {
    return PhyllotaxisPattern::kOppositeDecussate;
  }
  if (name == "whorled") return PhyllotaxisPattern::kWhorled;
  if (name == "spiral") return PhyllotaxisPattern::kSpiral;
  SYLVA_CHECK_INPUT(false, option)
      << "unknown phyllotaxis \"" << name << "\" (alternate, opposite_decussate, whorled, spiral)";
  return PhyllotaxisPattern::kSpiral;
}

void TreeMetricsOptions::Check() const {
  SYLVA_CHECK_INPUT(dbh_height_m > 0, "TreeMetrics.dbh_height_m") << "must be > 0";
  SYLVA_CHECK_INPUT(major_branch_fraction > 0 && major_branch_fraction <= 1,
                    "TreeMetrics.major_branch_fraction")
      << "must be in (0, 1]";
  SYLVA_CHECK_INPUT(crown_scale_fraction >= 0 && crown_scale_fraction < 1,
                    "TreeMetrics.crown_scale_fraction")
      << "must be in [0, 1)";
  SYLVA_CHECK_INPUT(density_support_fraction > 0 && density_support_fraction <= 1,
                    "TreeMetrics.density_support_fraction")
      << "must be in (0, 1]";
  SYLVA_CHECK_INPUT(direction_fraction > 0 && direction_fraction <= 1,
                    "TreeMetrics.direction_fraction")
      << "must be in (0, 1]";
}

void PenAndInkOptions::Check() const {
  SYLVA_CHECK_INPUT(image_size >= 64 && image_size <= 8192, "PenAndInk.image_size")
      << "must be in [64, 8192], got " << image_size;
  SYLVA_CHECK_INPUT(margin >= 0 && margin <= 0.4, "PenAndInk.margin")
      << "must be in [0, 0.4], got " << margin;
  SYLVA_CHECK_INPUT(sample_spacing_px > 0 && sample_spacing_px <= 10, "PenAndInk.sample_spacing_px")
      << "must be in (0, 10], got " << sample_spacing_px;
  SYLVA_CHECK_INPUT(crease_deg >= 0 && crease_deg <= 180, "PenAndInk.crease_deg")
      << "must be in [0, 180], got " << crease_deg;
  SYLVA_CHECK_INPUT(hatch_spacing_px >= 1 && hatch_spacing_px <= 100, "PenAndInk.hatch_spacing_px")
      << "must be in [1, 100], got " << hatch_spacing_px;
  SYLVA_CHECK_INPUT(
      hatch_tone >= 0 && hatch_tone <= 1 && cross_hatch_tone >= 0 && cross_hatch_tone <= 1,
      "PenAndInk.hatch_tone")
      << "the tones must be in [0, 1]";
  SYLVA_CHECK_INPUT(light_direction.allFinite() && light_direction.norm() > 0,
                    "PenAndInk.light_direction")
      << "must be a finite, non-zero vector";
  SYLVA_CHECK_INPUT(outline_width_px > 0 && hatch_width_px > 0 && construction_width_px > 0,
                    "PenAndInk.outline_width_px")
      << "ink widths must be > 0";
}

}  // namespace sylva
