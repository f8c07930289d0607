#include <sstream>

#include "core/util/check.h"
#include "simulate/neighbor_search.h"
#include "simulate/particle_flow.h"

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

}  // namespace sylva
