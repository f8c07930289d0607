// Phyllotaxis: where leaves sit along an axis (thesis 5.4; Wither et al.
// 2009 section 5.1; Anastacio et al. 2006).
//
// Leaves grow at nodes spaced `internode` apart along the axis. A node bears
// `m` leaves spread evenly around the axis (360/m degrees apart), and each
// node is turned by the divergence angle phi from the previous one:
//
//   pattern              m   phi (default)
//   alternate            1   180     distichous: two ranks of leaves
//   opposite_decussate   2    90     pairs, successive pairs crossed
//   whorled              n   180/n   successive whorls offset by half a gap
//   spiral               1   137.5°  the golden angle 360 (2 - phi_golden)
//
// Angles are azimuths about the axis in a frame carried along it by
// parallel transport (mesh/frames.h), so a curved axis does not add twist.
// Azimuth 0 is the world "up" direction (+Z) made perpendicular to the
// axis at its start (+X for a vertical axis), turning counter-clockwise seen
// from the axis' tip, so that on a horizontal shoot distichous leaves with
// the default first_azimuth of 90 degrees spread sideways, as they do on elm
// and beech shoots.
#ifndef SYLVA_MESH_PHYLLOTAXIS_H_
#define SYLVA_MESH_PHYLLOTAXIS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace sylva {

enum class PhyllotaxisPattern { kAlternate, kOppositeDecussate, kWhorled, kSpiral };

// "alternate" (also "distichous"), "opposite_decussate" (also "decussate"),
// "whorled", "spiral"; throws InputError(option, ...) otherwise.
PhyllotaxisPattern ParsePhyllotaxisPattern(const std::string& name, const std::string& option);
const char* PhyllotaxisPatternName(PhyllotaxisPattern pattern);

struct PhyllotaxisOptions {
  PhyllotaxisPattern pattern = PhyllotaxisPattern::kSpiral;
  // Degrees between successive nodes; 0 = the pattern's default (table
  // above). Anastacio et al. list 30 (monostichous), 120 (tristichous) and 90
  // (tetrastichous) as other single-leaf divergences.
  double divergence_deg = 0.0;
  // Leaves per node of the whorled pattern (>= 3; the others fix it).
  int leaves_per_whorl = 3;
  // Distance between successive nodes along the axis, world units (> 0).
  double internode = 0.05;
  // Arc length of the first node from the axis' start, in internodes
  // ([0, 1]); nodes continue while they fit on the axis.
  double first_node = 0.5;
  // Azimuth of the first node's first leaf, degrees (see the header).
  double first_azimuth_deg = 90.0;
  // Angle between a petiole and the axis' forward tangent, degrees in
  // (0, 180): 90 = perpendicular, smaller = leaning towards the tip.
  double insertion_deg = 60.0;

  int LeavesPerNode() const;
  double DivergenceDeg() const;  // the divergence in use
  // Throws InputError("Phyllotaxis.<field>", ...).
  void Check() const;
};

// Where a leaf joins its axis and how it points (world frame, unit vectors).
struct LeafAttachment {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();            // on the axis
  Eigen::Vector3d petiole_direction = Eigen::Vector3d::UnitX();  // leaf base -> tip
  // Perpendicular to the petiole, in the plane of petiole and axis tangent,
  // on the tip's side: the leaf's upper (adaxial) face looks up the shoot.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d axis_tangent = Eigen::Vector3d::UnitZ();
  double arc_length = 0.0;   // world units from the axis' start
  double azimuth_deg = 0.0;  // about the axis, unwrapped (see header)
  int node = 0;              // node index along the axis
};

// Leaf attachments along the polyline `axis` (>= 2 points, consecutive
// duplicates ignored), node by node from its start, leaves of one node in
// azimuth order. An axis shorter than the first node gets none.
std::vector<LeafAttachment> PlaceLeavesAlongAxis(const std::vector<Eigen::Vector3d>& axis,
                                                 const PhyllotaxisOptions& options);

// The unit vector perpendicular to `tangent` (non-zero) at `azimuth_deg`
// about it, counted from world up (+Z made perpendicular to the tangent; +X
// for a vertical tangent), counter-clockwise seen from the tangent's tip:
// the azimuth convention above, at a single point.
Eigen::Vector3d RadialDirection(const Eigen::Vector3d& tangent, double azimuth_deg);

// The divergence angle from attachment a to b, degrees in [0, 180]: the
// angle between their petioles projected on the plane normal to a's axis
// tangent (what a botanist measures looking down the shoot).
double DivergenceAngleDeg(const LeafAttachment& a, const LeafAttachment& b);

}  // namespace sylva

#endif  // SYLVA_MESH_PHYLLOTAXIS_H_
