// Moving frames along a sampled curve (thesis 5.2.2, eq. 5.15-5.24).
//
// A generalized cylinder needs a frame (T, N, B) at every sample of its axis
// to place the cross-section. Frenet frames (eq. 5.15-5.18) are analytic but
// undefined where the curvature vanishes and flip by 180 degrees at an
// inflection, twisting the tube. Parallel-transport frames (Hanson & Ma
// 1995) instead carry an initial frame along the curve by the smallest
// rotation that takes T_i to T_{i+1} (eq. 5.19-5.23), so they never flip and
// twist only as much as the curve's torsion demands.
#ifndef SYLVA_MESH_FRAMES_H_
#define SYLVA_MESH_FRAMES_H_

#include <Eigen/Core>
#include <vector>

namespace sylva {

// An orthonormal, right-handed frame: binormal = tangent x normal. A
// cross-section point with local coordinates (c_x, c_y) lies at
// position + c_x normal + c_y binormal (eq. 5.24).
struct CurveFrame {
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  Eigen::Vector3d binormal = Eigen::Vector3d::UnitY();
};

// A unit normal to start parallel transport with at the first of `tangents`
// (non-zero vectors, need not be unit length): the direction in which the
// tangent turns first (the Frenet principal normal of the discrete curve)
// if it turns by more than a negligible angle within the samples,
// otherwise a fixed perpendicular of the first tangent (the world axis
// least aligned with it, crossed with it), so the result is deterministic.
Eigen::Vector3d InitialNormal(const std::vector<Eigen::Vector3d>& tangents);

// Parallel-transport frames at the samples whose curve tangents are
// `tangents` (non-zero; need not be unit length). Frame 0 has normal
// `initial_normal` made perpendicular to the first tangent (must not be
// parallel to it). Frame i+1 is frame i rotated about
// A = T_i x T_{i+1} / |T_i x T_{i+1}| by the angle between the tangents, as
// the change of basis M_{i+1} M_i^T between the frames (T_i, A, T_i x A) and
// (T_{i+1}, A, T_{i+1} x A) of eq. 5.21-5.23 (no trigonometry). Where the
// tangents are (numerically) equal, A is undefined and the frame is only
// re-orthogonalised. Each normal is re-orthonormalised against its tangent,
// so frames stay orthonormal over any number of samples.
std::vector<CurveFrame> ParallelTransportFrames(const std::vector<Eigen::Vector3d>& tangents,
                                                const Eigen::Vector3d& initial_normal);
// Same, starting from InitialNormal(tangents).
std::vector<CurveFrame> ParallelTransportFrames(const std::vector<Eigen::Vector3d>& tangents);

// Frenet frames (eq. 5.15-5.18) from the curve's first and second
// derivatives at each sample: T = P'/|P'|, N along the part of P''
// perpendicular to P', B = T x N. Where that part vanishes (a straight
// piece, an inflection) the frame is undefined: normal and binormal are
// returned as zero vectors. For comparison and tests; meshes use
// ParallelTransportFrames.
std::vector<CurveFrame> FrenetFrames(const std::vector<Eigen::Vector3d>& first_derivatives,
                                     const std::vector<Eigen::Vector3d>& second_derivatives);

}  // namespace sylva

#endif  // SYLVA_MESH_FRAMES_H_
