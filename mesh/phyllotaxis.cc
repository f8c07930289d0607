#include "mesh/phyllotaxis.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/util/check.h"
#include "mesh/frames.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
// 360 (2 - golden ratio) degrees: 137.5077...
const double kGoldenAngleDeg = 360.0 * (2.0 - 0.5 * (1.0 + std::sqrt(5.0)));

// The axis without consecutive duplicates, and the cumulative arc length.
struct Polyline {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> arc;  // arc[i] = length up to points[i]

  explicit Polyline(const std::vector<Eigen::Vector3d>& axis) {
    for (const Eigen::Vector3d& p : axis) {
      if (!points.empty() && (p - points.back()).norm() <= 1e-12) continue;
      arc.push_back(points.empty() ? 0.0 : arc.back() + (p - points.back()).norm());
      points.push_back(p);
    }
  }
  int NumSegments() const { return static_cast<int>(points.size()) - 1; }
  // The segment holding arc length s (clamped to the axis).
  int SegmentAt(double s) const {
    const int i = static_cast<int>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin()) - 1;
    return std::clamp(i, 0, NumSegments() - 1);
  }
};

// World up made perpendicular to the first tangent (+X if vertical).
Eigen::Vector3d ReferenceNormal(const Eigen::Vector3d& tangent) {
  const Eigen::Vector3d t = tangent.normalized();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - t.z() * t;
  if (up.norm() < 1e-6) up = Eigen::Vector3d::UnitX() - t.x() * t;
  return up.normalized();
}

LeafAttachment MakeAttachment(const Eigen::Vector3d& position, const CurveFrame& frame,
                              double azimuth_deg, double insertion_deg) {
  const double a = azimuth_deg * kDegree, c = std::cos(insertion_deg * kDegree),
               s = std::sin(insertion_deg * kDegree);
  const Eigen::Vector3d radial = std::cos(a) * frame.normal + std::sin(a) * frame.binormal;
  LeafAttachment out;
  out.position = position;
  out.axis_tangent = frame.tangent;
  out.petiole_direction = (c * frame.tangent + s * radial).normalized();
  out.normal = (s * frame.tangent - c * radial).normalized();
  out.azimuth_deg = azimuth_deg;
  return out;
}

}  // namespace

const char* PhyllotaxisPatternName(PhyllotaxisPattern pattern) {
  switch (pattern) {
    case PhyllotaxisPattern::kAlternate:
      return "alternate";
    case PhyllotaxisPattern::kOppositeDecussate:
      return "opposite_decussate";
    case PhyllotaxisPattern::kWhorled:
      return "whorled";
    case PhyllotaxisPattern::kSpiral:
      break;
  }
  return "spiral";
}

int PhyllotaxisOptions::LeavesPerNode() const {
  switch (pattern) {
    case PhyllotaxisPattern::kOppositeDecussate:
      return 2;
    case PhyllotaxisPattern::kWhorled:
      return leaves_per_whorl;
    default:
      return 1;
  }
}

double PhyllotaxisOptions::DivergenceDeg() const {
  if (divergence_deg != 0.0) return divergence_deg;
  switch (pattern) {
    case PhyllotaxisPattern::kAlternate:
      return 180.0;
    case PhyllotaxisPattern::kOppositeDecussate:
      return 90.0;
    case PhyllotaxisPattern::kWhorled:
      return 180.0 / leaves_per_whorl;
    case PhyllotaxisPattern::kSpiral:
      break;
  }
  return kGoldenAngleDeg;
}

void PhyllotaxisOptions::Check() const {
  SYLVA_CHECK_INPUT(divergence_deg >= -360 && divergence_deg <= 360, "Phyllotaxis.divergence_deg")
      << "must be in [-360, 360] degrees (0 = the pattern's default), got " << divergence_deg;
  SYLVA_CHECK_INPUT(leaves_per_whorl >= 3 && leaves_per_whorl <= 32, "Phyllotaxis.leaves_per_whorl")
      << "must be between 3 and 32, got " << leaves_per_whorl;
  SYLVA_CHECK_INPUT(internode > 0 && std::isfinite(internode), "Phyllotaxis.internode")
      << "must be > 0 world units, got " << internode;
  SYLVA_CHECK_INPUT(first_node >= 0 && first_node <= 1, "Phyllotaxis.first_node")
      << "must be in [0, 1] internodes, got " << first_node;
  SYLVA_CHECK_INPUT(std::isfinite(first_azimuth_deg), "Phyllotaxis.first_azimuth_deg")
      << "must be finite";
  SYLVA_CHECK_INPUT(insertion_deg > 0 && insertion_deg < 180, "Phyllotaxis.insertion_deg")
      << "must be in (0, 180) degrees, got " << insertion_deg;
}

std::vector<LeafAttachment> PlaceLeavesAlongAxis(const std::vector<Eigen::Vector3d>& axis,
                                                 const PhyllotaxisOptions& options) {
  options.Check();
  const Polyline line(axis);
  std::vector<LeafAttachment> leaves;
  if (line.NumSegments() < 1) return leaves;
  std::vector<Eigen::Vector3d> tangents;
  for (int i = 0; i < line.NumSegments(); ++i) {
    tangents.push_back(line.points[i + 1] - line.points[i]);
  }
  const std::vector<CurveFrame> frames =
      ParallelTransportFrames(tangents, ReferenceNormal(tangents[0]));
  const int per_node = options.LeavesPerNode();
  const double divergence = options.DivergenceDeg();
  const double length = line.arc.back();
  for (int node = 0;; ++node) {
    const double s = (options.first_node + node) * options.internode;
    if (s > length + 1e-12 * length) break;
    const int segment = line.SegmentAt(s);
    const Eigen::Vector3d position =
        line.points[segment] + (s - line.arc[segment]) * frames[segment].tangent;
    for (int k = 0; k < per_node; ++k) {
      const double azimuth = options.first_azimuth_deg + node * divergence + k * 360.0 / per_node;
      LeafAttachment leaf =
          MakeAttachment(position, frames[segment], azimuth, options.insertion_deg);
      leaf.arc_length = s;
      leaf.node = node;
      leaves.push_back(leaf);
    }
  }
  return leaves;
}

Eigen::Vector3d RadialDirection(const Eigen::Vector3d& tangent, double azimuth_deg) {
  const Eigen::Vector3d t = tangent.normalized();
  const Eigen::Vector3d up = ReferenceNormal(t);
  return std::cos(azimuth_deg * kDegree) * up + std::sin(azimuth_deg * kDegree) * t.cross(up);
}

double DivergenceAngleDeg(const LeafAttachment& a, const LeafAttachment& b) {
  const Eigen::Vector3d t = a.axis_tangent.normalized();
  const Eigen::Vector3d pa = a.petiole_direction - a.petiole_direction.dot(t) * t;
  const Eigen::Vector3d pb = b.petiole_direction - b.petiole_direction.dot(t) * t;
  return std::atan2(pa.cross(pb).norm(), pa.dot(pb)) / kDegree;
}

}  // namespace sylva
