#include "simulate/particle_dynamics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva {
namespace {

// A particle falling from rest towards a very distant base (a constant pull g)
// against linear drag c has v(t) = (g / c)(1 - e^{-ct}) and
// x(t) = (g / c) t - (g / c^2)(1 - e^{-ct}).
TEST(ParticleDynamicsTest, Rk4MatchesTheAnalyticFallWithDrag) {
  ParticleFlowOptions options;
  options.base_pull = 2.0;
  options.damping = 0.7;
  const ConstantDirectionField no_field;
  const ParticleForces forces(options, Eigen::Vector3d(0, 0, -1e12), no_field, SimFrame());
  ParticleState state;
  const double h = 0.25;
  const int steps = 40;
  for (int s = 0; s < steps; ++s) state = Rk4Step(forces, FrozenNeighbor(), state, h);
  const double t = h * steps, g = 2.0, c = 0.7;
  EXPECT_NEAR(-state.position.z(), g / c * t - g / (c * c) * (1 - std::exp(-c * t)), 1e-6);
  EXPECT_NEAR(-state.velocity.z(), g / c * (1 - std::exp(-c * t)), 1e-6);
  EXPECT_NEAR(state.position.head<2>().norm(), 0.0, 1e-12);
}

TEST(ParticleDynamicsTest, StepDoublingErrorShrinksWithTheFifthPowerOfTheStep) {
  ParticleFlowOptions options;
  const ConstantDirectionField no_field;
  const ParticleForces forces(options, Eigen::Vector3d(0, 0, 0), no_field, SimFrame());
  ParticleState state;
  state.position = Eigen::Vector3d(10, 0, 5);
  state.velocity = Eigen::Vector3d(0, 3, 0);  // curves around the base
  double error_big = 0, error_small = 0;
  DoubledRk4Step(forces, FrozenNeighbor(), state, 0.8, &error_big);
  DoubledRk4Step(forces, FrozenNeighbor(), state, 0.4, &error_small);
  ASSERT_GT(error_small, 0);
  EXPECT_NEAR(std::log2(error_big / error_small), 5.0, 0.6);
}

TEST(ParticleDynamicsTest, NeighbourAttractionFallsToZeroAtItsRadius) {
  ParticleFlowOptions options;
  options.base_pull = 0;
  options.damping = 1;
  options.neighbor_radius = 4;
  const ConstantDirectionField no_field;
  const ParticleForces forces(options, Eigen::Vector3d::Zero(), no_field, SimFrame());
  ParticleState state;
  FrozenNeighbor neighbor;
  neighbor.pull = 2.0;
  neighbor.position = Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR(forces.Acceleration(state, neighbor).x(), 2.0 * std::pow(1 - 1.0 / 16, 2), 1e-12);
  neighbor.position = Eigen::Vector3d(0, 4.5, 0);
  EXPECT_EQ(forces.Acceleration(state, neighbor).norm(), 0.0);
}

TEST(ParticleDynamicsTest, FieldDirectionIsAddedWithItsWeight) {
  ParticleFlowOptions options;
  options.base_pull = 0;
  options.field_weight = 0.5;
  const ConstantDirectionField sideways(Eigen::Vector3d(0, 3, 0));
  const ParticleForces forces(options, Eigen::Vector3d::Zero(), sideways, SimFrame());
  const Eigen::Vector3d a = forces.Acceleration(ParticleState(), FrozenNeighbor());
  EXPECT_TRUE(a.isApprox(Eigen::Vector3d(0, 0.5, 0)));
}

TEST(StepControllerTest, ShrinksOnLargeErrorsAndGrowsOnSmallOnesWithinLimits) {
  StepController controller(0.5, 0.01, 1.0, 0.01);
  EXPECT_FALSE(controller.Judge(1.0));  // 100x the tolerance: rejected
  EXPECT_LT(controller.step(), 0.5);
  EXPECT_GE(controller.step(), 0.05);  // at most 10x smaller
  const double shrunk = controller.step();
  EXPECT_TRUE(controller.Judge(1e-6));
  EXPECT_NEAR(controller.step(), std::min(1.0, 5 * shrunk), 1e-12);  // at most 5x larger
  for (int i = 0; i < 10; ++i) controller.Judge(0.0);
  EXPECT_EQ(controller.step(), 1.0);
  StepController at_minimum(0.01, 0.01, 1.0, 0.01);
  EXPECT_TRUE(at_minimum.Judge(1.0));  // accepted at the smallest step
}

}  // namespace
}  // namespace sylva
