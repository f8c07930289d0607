// The 3D plant of a concept sketch (Anastacio et al. 2006, sections 5-7):
// organs placed along the stem at nodes in a phyllotactic pattern, sized by
// the boundary lines and inclined by the inclination lines, each a copy of
// the drawn organ templates mapped onto its reference line.
//
// World frame: the drawing's plane is x-z, the stem's base at the origin,
// +z up (the canvas' -y), +x the canvas' +x, +y into the page (seen from the
// front, the drawing's own view, +y points away from the viewer); world
// units per canvas pixel = stem_length / the stem's drawn length.
//
// Per node (paper 6.1-6.3; "layers" lie between consecutive inclination
// lines, `organs_per_layer` nodes each, evenly spaced in arc length from
// the upper line down; with fewer than two inclination lines the whole stem
// is one layer):
//   - B0, the node on the stem;
//   - the branching angles phi_L, phi_R from the stem's downward direction,
//     linearly interpolated between the layer's inclination lines (the
//     paper's angles alpha_i, beta_i);
//   - P_L, P_R: the rays from B0 turned by phi_L to the left and phi_R to
//     the right meet the envelope (the boundary lines); P_C: where P_L P_R
//     crosses the stem;
//   - theta': the previous organ's plus the divergence angle (the first
//     organ, at the top, at first_azimuth_deg; 0 = towards the drawing's
//     right, counter-clockwise seen from the stem's tip, from the top down);
//   - B1 = P_C + r(theta') (cos theta' e1 + sin theta' e2) on the two half
//     ellipses about P_C through the boundaries (semi-axes a to the left, c
//     to the right, b = (a + c) / 2 in depth), e1 the drawing plane's
//     normal to the stem at P_C pointing right, e2 = stem tangent x e1.
//     (The paper revolves in the plane through P_L and P_R; here the plane
//     is normal to the stem at P_C, with a and c measured there, which is
//     the same for a symmetric drawing and keeps the measured divergence
//     exact and the tip on the envelope.)
// The organ's frame (section 7): e3' along B0 B1, e1' = t x e3' (t the stem
// tangent), e2' = e3' x e1'; the organ template (u, v) is mapped to B0 +
// L (u e3' + v e1' + w e2'), w = a droop and a fold of the blade. L =
// |B0 B1|, reduced (by bisection) until every point of the organ lies inside
// the envelope of revolution: at the nearest stem point, within the half
// ellipses of that height (ConceptPlant::EnvelopeExcess).
#ifndef SYLVA_SKETCH_CONCEPT_PLANT_H_
#define SYLVA_SKETCH_CONCEPT_PLANT_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "core/types/triangle_mesh.h"
#include "sketch/concept_sketch.h"

namespace sylva {

struct ConceptPlantOptions {
  // "auto" (the pattern written in the drawing, else spiral) or a pattern
  // name (ConceptPatternFromName).
  std::string phyllotaxis = "auto";
  // Degrees between successive nodes; < 0 = the pattern's (paper: spiral
  // 137.5, monostichous 30, distichous 180, tristichous 120, tetrastichous
  // 90). 0 puts every node's organs on one side.
  double divergence_deg = -1.0;
  // Nodes per layer (the paper's "organs per layer"), >= 1.
  int organs_per_layer = 8;
  // Organs per node, spread evenly about the stem (2 with tetrastichous:
  // decussate pairs), in [1, 8].
  int organs_per_node = 1;
  // Azimuth of the first (top) organ, degrees.
  double first_azimuth_deg = 0.0;
  // Organs' angle from the stem's downward direction where the drawing has
  // no inclination line, degrees in (0, 180).
  double default_branching_deg = 120.0;
  // The stem's length in metres (a drawing has no scale), > 0.
  double stem_length = 0.3;
  // Stem radius at the base as a fraction of stem_length when the stroke
  // width is not given; (0, 0.2].
  double stem_radius_fraction = 0.015;
  // The stem's radius at its tip over its base radius, (0, 1].
  double stem_tip_fraction = 0.3;
  // The blade's tip hangs this far below its reference line, in organ
  // lengths (u^2 profile), [-1, 1].
  double organ_droop = 0.08;
  // The blade rises from its midrib to its edges at this angle, degrees in
  // [0, 60].
  double organ_fold_deg = 12.0;
  // Every organ is also an axis of the skeleton (its midrib or centre line),
  // so that the plant's exports (L-Py, MTG) carry the arrangement; line
  // organs always are.
  bool organ_axes = true;
  // Radius of an organ's axis as a fraction of its length, (0, 0.2].
  double organ_axis_radius_fraction = 0.012;
  // Seed of the organs' interpolation between the two drawn templates.
  uint64_t seed = 1;

  // Throws InputError("Concept.<field>", ...).
  void Check() const;
};

struct ConceptOrgan {
  int node = 0;                                             // node index from the top
  int layer = 0;                                            // layer index from the top
  Eigen::Vector3d base = Eigen::Vector3d::Zero();           // B0, on the stem
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();            // B0 + L e3'
  Eigen::Vector3d reference_tip = Eigen::Vector3d::Zero();  // B1, on the envelope
  Eigen::Vector3d stem_tangent = Eigen::Vector3d::UnitZ();  // at B0
  double stem_arc = 0.0;       // B0's arc length from the stem's base, world units
  double azimuth_deg = 0.0;    // theta', unwrapped
  double branching_deg = 0.0;  // phi of the side B1 lies on (interpolated)
  double length = 0.0;         // L, world units
  double fit = 1.0;            // L / |B0 B1| (< 1: shrunk to fit the envelope)
  double template_t = 0.0;     // interpolation between the two templates
  bool blade = true;
  std::vector<Eigen::Vector3d> centre;  // the midrib or centre line, base to tip
};

struct ConceptPlant {
  ConceptPattern pattern = ConceptPattern::kSpiral;
  double divergence_deg = 137.5;
  double world_per_pixel = 1.0;
  Eigen::Vector2d base_px = Eigen::Vector2d::Zero();  // the stem's base on the canvas
  std::vector<Eigen::Vector3d> stem;                  // world, base first
  std::vector<ConceptOrgan> organs;                   // from the top down
  TriangleMesh blades;  // the blade organs' surfaces, material "leaves"
  // The stem (order 0) and organ axes (order 1, blades' only with
  // organ_axes), with radii: what the exports (L-Py, MTG, QSM) carry.
  SkeletonGraph skeleton;
  // The stem and line organs (needles, branches): what is meshed as bark
  // (a blade is its surface; its midrib is drawn as a vein line).
  SkeletonGraph wood_skeleton;
  // The blades' midribs (their centre lines on the surface), base to tip.
  std::vector<std::vector<Eigen::Vector3d>> veins;
  // The construction lines in 3D for drawing: the stem, the boundaries and
  // inclination lines in the drawing plane, and the envelope's cross
  // section (the two half ellipses) at each inclination line.
  std::vector<std::vector<Eigen::Vector3d>> construction;
  int nodes_without_room = 0;  // nodes whose envelope is too narrow for an organ
  int shrunk_organs = 0;       // organs with fit < 0.999
  std::string brief;

  // A canvas point in the world frame (in the drawing plane).
  Eigen::Vector3d ToWorld(const Eigen::Vector2d& point_px) const;
  // How far `point` lies outside the envelope of revolution, world units
  // (<= 0 inside): at the nearest stem point, its distance from the stem
  // over the half ellipse's radius in its direction; beyond the stem's ends,
  // how far beyond.
  double EnvelopeExcess(const Eigen::Vector3d& point) const;

  // The envelope's half widths a (left) and c (right) at arc lengths
  // envelope_arc (world units), normal to the stem in the drawing plane.
  std::vector<double> envelope_arc, envelope_left, envelope_right;
};

// Throws InputError naming the option or structure.source.
ConceptPlant BuildConceptPlant(const ConceptStructure& structure,
                               const ConceptPlantOptions& options);

// The divergence from organ a to organ b as a botanist measures it looking
// down the stem: the angle between their reference lines (base to tip)
// projected on the plane normal to a's stem tangent, degrees in [0, 180].
double MeasuredDivergenceDeg(const ConceptOrgan& a, const ConceptOrgan& b);

}  // namespace sylva

#endif  // SYLVA_SKETCH_CONCEPT_PLANT_H_
