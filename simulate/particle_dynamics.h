// The equations of motion of the particle flow (see particle_flow.h) and
// their adaptive RK4 integration. Internal to simulate/.
#ifndef SYLVA_SIMULATE_PARTICLE_DYNAMICS_H_
#define SYLVA_SIMULATE_PARTICLE_DYNAMICS_H_

#include <Eigen/Core>

#include "simulate/direction_field.h"
#include "simulate/particle_flow.h"

namespace sylva {

// The simulation frame: the density grid's voxel index frame shifted so that
// the lowest active voxel's centre is at the origin (small coordinates keep
// float storage of traces exact to ~1e-5 voxels). Lengths are in voxels.
struct SimFrame {
  Eigen::Vector3d origin_in_world = Eigen::Vector3d::Zero();  // sim (0, 0, 0)
  double voxel_size = 1.0;                                    // world units per voxel

  Eigen::Vector3d WorldFromSim(const Eigen::Vector3d& point_in_sim) const {
    return origin_in_world + voxel_size * point_in_sim;
  }
  Eigen::Vector3d SimFromWorld(const Eigen::Vector3d& point_in_world) const {
    return (point_in_world - origin_in_world) / voxel_size;
  }
};

struct ParticleState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // sim frame, voxels
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // voxels per time unit
};

// The nearest neighbour as seen during one step: frozen where it was when
// the step began. `pull` = neighbor_pull * 2 m_j / (m_i + m_j); 0 = none.
struct FrozenNeighbor {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // sim frame
  double pull = 0.0;                                   // voxels / time^2
};

// The accelerations of particle_flow.h's model. Thread-safe (const).
class ParticleForces {
 public:
  ParticleForces(const ParticleFlowOptions& options, const Eigen::Vector3d& base_in_sim,
                 const DirectionField& field, const SimFrame& frame);

  Eigen::Vector3d Acceleration(const ParticleState& state, const FrozenNeighbor& neighbor) const;

  // Where the base pull heads from `position`: a point on the vertical axis
  // through the base, below the particle (see ParticleFlowOptions).
  Eigen::Vector3d BaseTarget(const Eigen::Vector3d& position_in_sim) const;

 private:
  Eigen::Vector3d base_in_sim_;
  double descent_slope_;   // tan(descent_angle); +inf heads straight for the base
  double axis_lookahead_;  // voxels
  double base_pull_;
  double neighbor_radius2_;
  double field_weight_;
  double damping_;
  const DirectionField& field_;
  bool field_is_constant_ = false;
  // field_weight * the direction of a constant field, else zero.
  Eigen::Vector3d constant_field_acceleration_ = Eigen::Vector3d::Zero();
  SimFrame frame_;
};

// One classical RK4 step of size h (thesis eq. 3.6) of [x, v]' = [v, a].
ParticleState Rk4Step(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                      const ParticleState& state, double h);

// Step doubling: one step of h against two of h / 2. Returns the two-step
// result with local extrapolation (fifth order); `*error` receives the
// distance between the two positions, in voxels.
ParticleState DoubledRk4Step(const ParticleForces& forces, const FrozenNeighbor& neighbor,
                             const ParticleState& state, double h, double* error);

// Step-size control for step doubling (Numerical Recipes' rkqs, safety 0.9):
// shrinks after a rejected trial, grows after an accepted one, within
// [min_step, max_step].
class StepController {
 public:
  StepController(double initial_step, double min_step, double max_step, double tolerance);

  // The step size to try next, in time units.
  double step() const { return step_; }
  // Judges a trial of step() whose largest error was `error` (voxels): true
  // to accept it (always at min_step), false to retry with the new step().
  bool Judge(double error);

 private:
  double step_, min_step_, max_step_, tolerance_;
};

}  // namespace sylva

#endif  // SYLVA_SIMULATE_PARTICLE_DYNAMICS_H_
