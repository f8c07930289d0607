// The simulate module's option checks and option-value parsers, apart from
// the algorithms so that reading and checking a project's options
// (ui/pipeline, fuzz/project_fuzzer.cc) does not link them.
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "simulate/attractor_field.h"
#include "simulate/neighbor_search.h"
#include "simulate/particle_flow.h"
#include "simulate/skeleton_consolidation.h"
#include "simulate/skeleton_pruning.h"

namespace sylva {
namespace {

// Particle counts above this would overflow the trace graph's int32 indices
// within a few hundred steps.
constexpr int kMaxParticles = 10'000'000;

void CheckPositive(double value, const char* field) {
  SYLVA_CHECK_INPUT(value > 0 && std::isfinite(value), std::string("ParticleFlow.") + field)
      << "must be positive and finite, got " << value;
}

void CheckNonNegative(double value, const char* field) {
  SYLVA_CHECK_INPUT(value >= 0 && std::isfinite(value), std::string("ParticleFlow.") + field)
      << "must be >= 0 and finite, got " << value;
}

}  // namespace

void ParticleFlowOptions::Check() const {
  SYLVA_CHECK_INPUT(num_particles >= 1 && num_particles <= kMaxParticles,
                    "ParticleFlow.num_particles")
      << "must be between 1 and " << kMaxParticles << ", got " << num_particles;
  SYLVA_CHECK_INPUT(seed_exponent >= 0 && seed_exponent <= 4, "ParticleFlow.seed_exponent")
      << "must be between 0 and 4, got " << seed_exponent;
  CheckNonNegative(base_pull, "base_pull");
  SYLVA_CHECK_INPUT(descent_angle_deg > 0 && descent_angle_deg <= 90,
                    "ParticleFlow.descent_angle_deg")
      << "must be in (0, 90] degrees, got " << descent_angle_deg;
  CheckPositive(axis_lookahead, "axis_lookahead");
  CheckNonNegative(neighbor_pull, "neighbor_pull");
  CheckPositive(neighbor_radius, "neighbor_radius");
  SYLVA_CHECK_INPUT(std::isfinite(field_weight), "ParticleFlow.field_weight")
      << "must be finite, got " << field_weight;
  CheckPositive(damping, "damping");
  CheckNonNegative(merge_distance, "merge_distance");
  CheckNonNegative(base_radius, "base_radius");
  SYLVA_CHECK_INPUT(max_iterations >= 0 && max_iterations <= 1'000'000,
                    "ParticleFlow.max_iterations")
      << "must be between 0 and 1000000, got " << max_iterations;
  CheckPositive(error_tolerance, "error_tolerance");
  CheckPositive(min_step, "min_step");
  CheckPositive(max_step, "max_step");
  SYLVA_CHECK_INPUT(min_step <= max_step, "ParticleFlow.max_step")
      << "must be >= ParticleFlow.min_step (" << min_step << "), got " << max_step;
  SYLVA_CHECK_INPUT(initial_step >= min_step && initial_step <= max_step,
                    "ParticleFlow.initial_step")
      << "must be within [min_step, max_step] = [" << min_step << ", " << max_step << "], got "
      << initial_step;
  SYLVA_CHECK_INPUT(flowing_join_angle_deg >= 0 && flowing_join_angle_deg <= 180,
                    "ParticleFlow.flowing_join_angle_deg")
      << "must be in [0, 180] degrees, got " << flowing_join_angle_deg;
  CheckNonNegative(trace_tolerance, "trace_tolerance");
  CheckNonNegative(simplify_tolerance, "simplify_tolerance");
  NeighborSearchKindFromName(neighbor_search, "ParticleFlow.neighbor_search");
}

std::string ParticleFlowSummary::BriefReport() const {
  std::ostringstream out;
  out << "Particle flow: " << seeded << " particles, " << merges << " merges; " << reached_base
      << " reached the base (" << trace_joins << " bundles by joining finished traces); "
      << flowing_joins << " bundles joined the traces of flowing ones";
  if (unfinished > 0) {
    out << ", " << unfinished << " in " << unfinished_bundles
        << " bundles did not and were joined to the root by straight edges";
  }
  out << ". " << iterations << " steps (" << rejected_steps << " rejected, final step "
      << final_step << ", time " << simulated_time << "), " << particle_steps << " particle steps, "
      << neighbor_queries << " neighbour queries (" << neighbor_search << "). Traces " << raw_nodes
      << " nodes, skeleton " << skeleton_nodes << " nodes. Time " << seconds_total << " s (seed "
      << seconds_seed << ", neighbours and merges " << seconds_neighbors << ", arrivals and joins "
      << seconds_join << ", integrate " << seconds_integrate << ", skeleton " << seconds_skeleton
      << ").";
  return out.str();
}

NeighborSearchKind NeighborSearchKindFromName(const std::string& name, const std::string& source) {
  if (name == "uniform_grid") return NeighborSearchKind::kUniformGrid;
  if (name == "embree") return NeighborSearchKind::kEmbree;
  if (name == "brute_force") return NeighborSearchKind::kBruteForce;
  SYLVA_INPUT_ERROR(source) << "must be 'uniform_grid', 'embree' or 'brute_force', got '" << name
                            << "'";
  return NeighborSearchKind::kUniformGrid;  // not reached
}

const char* NeighborSearchName(NeighborSearchKind kind) {
  switch (kind) {
    case NeighborSearchKind::kUniformGrid:
      return "uniform_grid";
    case NeighborSearchKind::kEmbree:
      return "embree";
    case NeighborSearchKind::kBruteForce:
      return "brute_force";
  }
  return "?";
}

void TreeBaseOptions::Check() const {
  SYLVA_CHECK_INPUT(min_opacity >= 0 && min_opacity < 1, "TreeBase.min_opacity")
      << "must be in [0, 1), got " << min_opacity;
  SYLVA_CHECK_INPUT(layer_fraction > 0 && layer_fraction <= 1, "TreeBase.layer_fraction")
      << "must be in (0, 1], got " << layer_fraction;
  SYLVA_CHECK_INPUT(reference_voxels >= 1, "TreeBase.reference_voxels")
      << "must be >= 1, got " << reference_voxels;
  SYLVA_CHECK_INPUT(slab_voxels >= 1, "TreeBase.slab_voxels")
      << "must be >= 1, got " << slab_voxels;
}

void AttractorFieldOptions::Check() const {
  SYLVA_CHECK_INPUT(resolution >= 2 && resolution <= 4096, "DirectionField.resolution")
      << "must be between 2 and 4096 cells, got " << resolution;
  SYLVA_CHECK_INPUT(blend == "linear" || blend == "constant", "DirectionField.blend")
      << "must be 'linear' or 'constant', got '" << blend << "'";
  SYLVA_CHECK_INPUT(falloff > 0 && std::isfinite(falloff), "DirectionField.falloff")
      << "must be a positive fraction of the image size, got " << falloff;
  SYLVA_CHECK_INPUT(constant_h > 0 && constant_h < 1, "DirectionField.constant_h")
      << "must be in (0, 1), got " << constant_h;
  SYLVA_CHECK_INPUT(combine == "average" || combine == "intersect", "DirectionField.combine")
      << "must be 'average' or 'intersect', got '" << combine << "'";
  SYLVA_CHECK_INPUT(resolution_3d >= 2 && resolution_3d <= 1024, "DirectionField.resolution_3d")
      << "must be between 2 and 1024 cells, got " << resolution_3d;
}

void MattePruningOptions::Check() const {
  SYLVA_CHECK_INPUT(max_strand_fraction >= 0 && max_strand_fraction <= 1,
                    "Skeleton.prune_max_strand_fraction")
      << "must be in [0, 1], got " << max_strand_fraction;
  SYLVA_CHECK_INPUT(max_outside_fraction >= 0 && max_outside_fraction < 1,
                    "Skeleton.prune_max_outside_fraction")
      << "must be in [0, 1), got " << max_outside_fraction;
  SYLVA_CHECK_INPUT(matte_threshold >= 0 && matte_threshold < 1, "Skeleton.prune_matte_threshold")
      << "must be in [0, 1), got " << matte_threshold;
  SYLVA_CHECK_INPUT(sample_spacing_fraction > 0 && sample_spacing_fraction < 1,
                    "Skeleton.prune_sample_spacing_fraction")
      << "must be in (0, 1), got " << sample_spacing_fraction;
}

void ConsolidationOptions::Check() const {
  SYLVA_CHECK_INPUT(redundancy_fraction >= 0 && redundancy_fraction < 1,
                    "Skeleton.redundancy_fraction")
      << "must be in [0, 1), got " << redundancy_fraction;
  SYLVA_CHECK_INPUT(min_support >= 0 && min_support <= 1, "Skeleton.min_support")
      << "must be in [0, 1], got " << min_support;
  SYLVA_CHECK_INPUT(support_radius_voxels >= 1 && support_radius_voxels <= 8,
                    "Skeleton.support_radius_voxels")
      << "must be in [1, 8], got " << support_radius_voxels;
  SYLVA_CHECK_INPUT(support_opacity > 0 && support_opacity <= 1, "Skeleton.support_opacity")
      << "must be in (0, 1], got " << support_opacity;
  SYLVA_CHECK_INPUT(zip_radius_voxels >= 0 && zip_radius_voxels <= 8, "Skeleton.zip_radius_voxels")
      << "must be in [0, 8], got " << zip_radius_voxels;
  SYLVA_CHECK_INPUT(duplicate_radius_voxels >= 0 && duplicate_radius_voxels <= 8,
                    "Skeleton.duplicate_radius_voxels")
      << "must be in [0, 8], got " << duplicate_radius_voxels;
  SYLVA_CHECK_INPUT(max_strand_fraction >= 0 && max_strand_fraction <= 1,
                    "Skeleton.thin_strand_fraction")
      << "must be in [0, 1], got " << max_strand_fraction;
  SYLVA_CHECK_INPUT(max_empty_fraction >= 0 && max_empty_fraction <= 1,
                    "Skeleton.max_empty_fraction")
      << "must be in [0, 1], got " << max_empty_fraction;
  SYLVA_CHECK_INPUT(base_fraction >= 0 && base_fraction < 1, "Skeleton.base_fraction")
      << "must be in [0, 1), got " << base_fraction;
  SYLVA_CHECK_INPUT(sample_spacing_fraction > 0 && sample_spacing_fraction < 1,
                    "Skeleton.consolidate_sample_spacing_fraction")
      << "must be in (0, 1), got " << sample_spacing_fraction;
}

}  // namespace sylva
