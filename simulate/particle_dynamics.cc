#include "simulate/particle_dynamics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {
namespace {

// Numerical Recipes' controller constants (rkqs): safety factor, and the
// largest growth and shrink factors per step.
constexpr double kSafety = 0.9;
constexpr double kMaxGrowth = 5.0;
constexpr double kMaxShrink = 0.1;

struct Derivative {
  Eigen::Vector3d position_rate;  // = velocity
  Eigen::Vector3d velocity_rate;  // = acceleration
};

Derivative Evaluate(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                    const ParticleState& state) {
  return {state.velocity, forces.Acceleration(state, neighbor)};
}

ParticleState Offset(const ParticleState& state, const Derivative& rate, double h) {
  return {state.position + h * rate.position_rate, state.velocity + h * rate.velocity_rate};
}

// One RK4 step whose first stage k1 = f(state) is already known.
ParticleState Rk4StepFrom(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                          const ParticleState& state, const Derivative& k1, double h) {
  const Derivative k2 = Evaluate(forces, neighbor, Offset(state, k1, h / 2));
  const Derivative k3 = Evaluate(forces, neighbor, Offset(state, k2, h / 2));
  const Derivative k4 = Evaluate(forces, neighbor, Offset(state, k3, h));
  ParticleState next;
  next.position = state.position + (h / 6) * (k1.position_rate + 2 * k2.position_rate +
                                              2 * k3.position_rate + k4.position_rate);
  next.velocity = state.velocity + (h / 6) * (k1.velocity_rate + 2 * k2.velocity_rate +
                                              2 * k3.velocity_rate + k4.velocity_rate);
  return next;
}

}  // namespace

ParticleForces::ParticleForces(const ParticleFlowOptions& options,
                               const Eigen::Vector3d& base_in_sim, const DirectionField& field,
                               const SimFrame& frame)
    : base_in_sim_(base_in_sim),
      descent_slope_(options.descent_angle_deg >= 90
                         ? std::numeric_limits<double>::infinity()
                         : std::tan(options.descent_angle_deg * M_PI / 180)),
      axis_lookahead_(options.axis_lookahead),
      base_pull_(options.base_pull),
      neighbor_radius2_(options.neighbor_radius * options.neighbor_radius),
      field_weight_(options.field_weight),
      damping_(options.damping),
      field_(field),
      frame_(frame) {
  // A constant field needs no call per evaluation (the common case: none).
  if (const auto* constant = dynamic_cast<const ConstantDirectionField*>(&field)) {
    constant_field_acceleration_ = field_weight_ * constant->Direction(Eigen::Vector3d::Zero());
    field_is_constant_ = true;
  }
}

Eigen::Vector3d ParticleForces::BaseTarget(const Eigen::Vector3d& position_in_sim) const {
  const double axis_distance = (base_in_sim_ - position_in_sim).head<2>().norm();
  const double drop = std::max(axis_distance * descent_slope_, axis_lookahead_);
  const double height = std::max(base_in_sim_.z(), position_in_sim.z() - drop);
  return Eigen::Vector3d(base_in_sim_.x(), base_in_sim_.y(), height);
}

Eigen::Vector3d ParticleForces::Acceleration(const ParticleState& state,
                                             const FrozenNeighbor& neighbor) const {
  Eigen::Vector3d acceleration = constant_field_acceleration_ - damping_ * state.velocity;
  const Eigen::Vector3d to_base = BaseTarget(state.position) - state.position;
  const double base_distance = to_base.norm();
  if (base_distance > 0) acceleration += (base_pull_ / base_distance) * to_base;
  if (neighbor.pull > 0) {
    // Attraction with the smooth falloff (1 - (d / r)^2)^2.
    const Eigen::Vector3d to_neighbor = neighbor.position - state.position;
    const double d2 = to_neighbor.squaredNorm();
    if (d2 > 0 && d2 < neighbor_radius2_) {
      const double falloff = 1.0 - d2 / neighbor_radius2_;
      acceleration += (neighbor.pull * falloff * falloff / std::sqrt(d2)) * to_neighbor;
    }
  }
  if (!field_is_constant_ && field_weight_ != 0) {
    acceleration += field_weight_ * field_.Direction(frame_.WorldFromSim(state.position));
  }
  return acceleration;
}

ParticleState Rk4Step(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                      const ParticleState& state, double h) {
  return Rk4StepFrom(forces, neighbor, state, Evaluate(forces, neighbor, state), h);
}

ParticleState DoubledRk4Step(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                             const ParticleState& state, double h, double* error) {
  // The big step and the first half step share their first stage.
  const Derivative k1 = Evaluate(forces, neighbor, state);
  const ParticleState big = Rk4StepFrom(forces, neighbor, state, k1, h);
  const ParticleState half = Rk4StepFrom(forces, neighbor, state, k1, h / 2);
  const ParticleState two = Rk4Step(forces, neighbor, half, h / 2);
  *error = (two.position - big.position).norm();
  // Local extrapolation: the two-step result's error is ~1/15 of the difference.
  return {two.position + (two.position - big.position) / 15,
          two.velocity + (two.velocity - big.velocity) / 15};
}

StepController::StepController(double initial_step, double min_step, double max_step,
                               double tolerance)
    : step_(std::clamp(initial_step, min_step, max_step)),
      min_step_(min_step),
      max_step_(max_step),
      tolerance_(tolerance) {}

bool StepController::Judge(double error) {
  const double ratio = error / tolerance_;
  if (ratio <= 1.0 || step_ <= min_step_) {
    const double growth =
        ratio > std::pow(kMaxGrowth / kSafety, -5.0) ? kSafety * std::pow(ratio, -0.2) : kMaxGrowth;
    step_ = std::clamp(step_ * growth, min_step_, max_step_);
    return true;
  }
  const double shrink = std::max(kSafety * std::pow(ratio, -0.25), kMaxShrink);
  step_ = std::max(step_ * shrink, min_step_);
  return false;
}

}  // namespace sylva
