#include "mesh/frames.h"

#include <Eigen/Geometry>

#include "core/util/check.h"

namespace sylva {
namespace {

// Below this |T_i x T_{i+1}| (the sine of the turn) two unit tangents count
// as equal and the rotation axis of eq. 5.19 as undefined.
constexpr double kParallelSine = 1e-12;
// The smallest tangent turn, in radians (as a sine), that InitialNormal takes
// as curvature rather than rounding noise.
constexpr double kCurvatureSine = 1e-6;

// `v` made perpendicular to unit `tangent` and unit length.
Eigen::Vector3d PerpendicularUnit(const Eigen::Vector3d& v, const Eigen::Vector3d& tangent) {
  return (v - v.dot(tangent) * tangent).normalized();
}

// The unit world axis crossed with `tangent`, choosing the axis least aligned with it.
Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& tangent) {
  Eigen::Index axis;
  tangent.cwiseAbs().minCoeff(&axis);
  return tangent.cross(Eigen::Vector3d::Unit(axis)).normalized();
}

CurveFrame MakeFrame(const Eigen::Vector3d& tangent, const Eigen::Vector3d& normal) {
  CurveFrame frame;
  frame.tangent = tangent;
  frame.normal = PerpendicularUnit(normal, tangent);
  frame.binormal = tangent.cross(frame.normal);
  return frame;
}

// Eq. 5.19-5.23: the normal of `frame` rotated by the rotation that takes its
// tangent to unit `next_tangent` about their common perpendicular A.
Eigen::Vector3d TransportNormal(const CurveFrame& frame, const Eigen::Vector3d& next_tangent) {
  const Eigen::Vector3d cross = frame.tangent.cross(next_tangent);
  const double sine = cross.norm();
  if (sine < kParallelSine) return frame.normal;  // T_i = T_{i+1}: no rotation
  const Eigen::Vector3d axis = cross / sine;
  const Eigen::Vector3d& normal = frame.normal;
  // N_{i+1} = M_{i+1} M_i^T N_i with M = [T, A, T x A] (columns).
  return next_tangent * frame.tangent.dot(normal) + axis * axis.dot(normal) +
         next_tangent.cross(axis) * frame.tangent.cross(axis).dot(normal);
}

}  // namespace

Eigen::Vector3d InitialNormal(const std::vector<Eigen::Vector3d>& tangents) {
  SYLVA_CHECK(!tangents.empty());
  const Eigen::Vector3d first = tangents[0].normalized();
  for (const Eigen::Vector3d& tangent : tangents) {
    const Eigen::Vector3d unit = tangent.normalized();
    const Eigen::Vector3d turn = unit - unit.dot(first) * first;
    if (turn.norm() > kCurvatureSine) return turn.normalized();
  }
  return AnyPerpendicular(first);
}

std::vector<CurveFrame> ParallelTransportFrames(const std::vector<Eigen::Vector3d>& tangents,
                                                const Eigen::Vector3d& initial_normal) {
  std::vector<CurveFrame> frames;
  if (tangents.empty()) return frames;
  frames.reserve(tangents.size());
  const Eigen::Vector3d first = tangents[0].normalized();
  SYLVA_CHECK(first.allFinite() && first.cross(initial_normal).norm() > 0)
      << "the initial normal must not be parallel to the first tangent";
  frames.push_back(MakeFrame(first, initial_normal));
  for (size_t i = 1; i < tangents.size(); ++i) {
    const Eigen::Vector3d tangent = tangents[i].normalized();
    SYLVA_DCHECK(tangent.allFinite()) << "zero tangent at sample " << i;
    frames.push_back(MakeFrame(tangent, TransportNormal(frames.back(), tangent)));
  }
  return frames;
}

std::vector<CurveFrame> ParallelTransportFrames(const std::vector<Eigen::Vector3d>& tangents) {
  if (tangents.empty()) return {};
  return ParallelTransportFrames(tangents, InitialNormal(tangents));
}

std::vector<CurveFrame> FrenetFrames(const std::vector<Eigen::Vector3d>& first_derivatives,
                                     const std::vector<Eigen::Vector3d>& second_derivatives) {
  SYLVA_CHECK(first_derivatives.size() == second_derivatives.size());
  std::vector<CurveFrame> frames(first_derivatives.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    const Eigen::Vector3d tangent = first_derivatives[i].normalized();
    // Eq. 5.16-5.17: the curvature vector, P'' without its part along P'.
    const Eigen::Vector3d& second = second_derivatives[i];
    const Eigen::Vector3d curvature = second - second.dot(tangent) * tangent;
    frames[i].tangent = tangent;
    if (curvature.norm() <= kCurvatureSine * second.norm() || curvature.isZero(0.0)) {
      frames[i].normal = frames[i].binormal = Eigen::Vector3d::Zero();
      continue;
    }
    frames[i].normal = curvature.normalized();
    frames[i].binormal = tangent.cross(frames[i].normal);
  }
  return frames;
}

}  // namespace sylva
