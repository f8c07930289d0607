#include "mesh/frames.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

void ExpectOrthonormalRightHanded(const std::vector<CurveFrame>& frames, double tolerance) {
  for (size_t i = 0; i < frames.size(); ++i) {
    const CurveFrame& f = frames[i];
    EXPECT_NEAR(f.tangent.norm(), 1.0, tolerance) << i;
    EXPECT_NEAR(f.normal.norm(), 1.0, tolerance) << i;
    EXPECT_NEAR(f.tangent.dot(f.normal), 0.0, tolerance) << i;
    EXPECT_LT((f.tangent.cross(f.normal) - f.binormal).norm(), tolerance) << i;
  }
}

// Helix (a cos t, a sin t, b t) sampled at t = i dt: first and second derivatives.
struct Helix {
  double a = 1.0, b = 0.5;
  Eigen::Vector3d First(double t) const { return {-a * std::sin(t), a * std::cos(t), b}; }
  Eigen::Vector3d Second(double t) const { return {-a * std::cos(t), -a * std::sin(t), 0.0}; }
  double Torsion() const { return b / (a * a + b * b); }
  double Speed() const { return std::sqrt(a * a + b * b); }
};

TEST(FramesTest, StraightLineFramesAreIdentical) {
  const std::vector<Eigen::Vector3d> tangents(50, Eigen::Vector3d(1.0, 2.0, -0.5));
  const std::vector<CurveFrame> frames = ParallelTransportFrames(tangents);
  ExpectOrthonormalRightHanded(frames, 1e-14);
  for (const CurveFrame& frame : frames) {
    EXPECT_EQ(frame.normal, frames[0].normal);
    EXPECT_EQ(frame.binormal, frames[0].binormal);
  }
  // No curvature: a fixed perpendicular (deterministic).
  EXPECT_NEAR(frames[0].normal.dot(tangents[0]), 0.0, 1e-14);
  EXPECT_EQ(InitialNormal(tangents), InitialNormal(tangents));
}

TEST(FramesTest, InitialNormalPointsWhereTheCurveTurns) {
  // A planar arc in the XY plane starting along +X and turning towards +Y.
  std::vector<Eigen::Vector3d> tangents;
  for (int i = 0; i < 10; ++i) tangents.emplace_back(std::cos(0.1 * i), std::sin(0.1 * i), 0.0);
  EXPECT_LT((InitialNormal(tangents) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  // Straight first, then turning: the first turn decides.
  tangents.insert(tangents.begin(), 3, Eigen::Vector3d::UnitX());
  EXPECT_LT((InitialNormal(tangents) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
}

TEST(FramesTest, HelixFramesTurnNoMoreThanTheTangentAndTwistByTheTorsion) {
  const Helix helix;
  const double dt = 2 * M_PI / 400;
  std::vector<Eigen::Vector3d> first, second;
  for (int i = 0; i <= 400; ++i) {
    first.push_back(helix.First(i * dt));
    second.push_back(helix.Second(i * dt));
  }
  const std::vector<CurveFrame> frenet = FrenetFrames(first, second);
  const std::vector<CurveFrame> frames = ParallelTransportFrames(first, frenet[0].normal);
  ExpectOrthonormalRightHanded(frames, 1e-12);
  ExpectOrthonormalRightHanded(frenet, 1e-12);
  for (size_t i = 0; i + 1 < frames.size(); ++i) {
    const double normal_turn = AngleBetween(frames[i].normal, frames[i + 1].normal);
    const double tangent_turn = AngleBetween(frames[i].tangent, frames[i + 1].tangent);
    EXPECT_LE(normal_turn, tangent_turn + 1e-12) << i;
  }
  // A rotation-minimising frame lags the Frenet frame by the integrated
  // torsion: angle(N_frenet, N_transport) = tau * s.
  for (size_t i = 0; i < frames.size(); i += 50) {
    const double s = i * dt * helix.Speed();
    const double lag = AngleBetween(frenet[i].normal, frames[i].normal);
    EXPECT_NEAR(lag, helix.Torsion() * s, 1e-3) << i;
  }
}

TEST(FramesTest, FrenetFlipsAtAnInflectionButTransportDoesNot) {
  // S-curve (t, sin t, 0): an inflection at t = pi, between two samples.
  std::vector<Eigen::Vector3d> first, second;
  for (double t = 0.05; t < 2 * M_PI; t += 0.1) {
    first.emplace_back(1.0, std::cos(t), 0.0);
    second.emplace_back(0.0, -std::sin(t), 0.0);
  }
  const std::vector<CurveFrame> frenet = FrenetFrames(first, second);
  const std::vector<CurveFrame> frames = ParallelTransportFrames(first);
  double worst_frenet = 0.0, worst_transport = 0.0;
  for (size_t i = 0; i + 1 < frames.size(); ++i) {
    worst_frenet = std::max(worst_frenet, AngleBetween(frenet[i].normal, frenet[i + 1].normal));
    worst_transport =
        std::max(worst_transport, AngleBetween(frames[i].normal, frames[i + 1].normal));
  }
  EXPECT_GT(worst_frenet, 0.9 * M_PI);  // the flip
  EXPECT_LT(worst_transport, 0.1);      // at most the tangent turn of one step
  ExpectOrthonormalRightHanded(frames, 1e-12);
}

TEST(FramesTest, FrenetIsUndefinedOnStraightPieces) {
  const std::vector<CurveFrame> frenet =
      FrenetFrames({Eigen::Vector3d::UnitX()}, {Eigen::Vector3d::UnitX()});
  EXPECT_EQ(frenet[0].normal, Eigen::Vector3d::Zero());
}

TEST(FramesTest, PlanarLoopReturnsToItsStartingFrame) {
  // A planar curve has no torsion: transport around a full circle gives
  // back the initial normal (no accumulated twist), over many small steps.
  const int steps = 100000;
  std::vector<Eigen::Vector3d> tangents;
  for (int i = 0; i <= steps; ++i) {
    const double angle = 2 * M_PI * i / steps;
    tangents.emplace_back(-std::sin(angle), std::cos(angle), 0.0);
  }
  const Eigen::Vector3d tilted = Eigen::Vector3d(-1.0, 0.0, 1.0).normalized();
  const std::vector<CurveFrame> frames = ParallelTransportFrames(tangents, tilted);
  EXPECT_LT((frames.back().normal - frames.front().normal).norm(), 1e-9);
  ExpectOrthonormalRightHanded({frames.back()}, 1e-13);
  // The out-of-plane component is conserved all the way round.
  for (size_t i = 0; i < frames.size(); i += 997) {
    EXPECT_NEAR(frames[i].normal.z(), tilted.z(), 1e-9) << i;
  }
}

TEST(FramesTest, InitialNormalParallelToTangentIsRefused) {
  EXPECT_THROW(ParallelTransportFrames({Eigen::Vector3d::UnitZ()}, Eigen::Vector3d::UnitZ()),
               Error);
  EXPECT_TRUE(ParallelTransportFrames({}).empty());
}

}  // namespace
}  // namespace sylva
