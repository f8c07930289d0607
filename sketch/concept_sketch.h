// Concept sketches of plant structure (Anastacio, Sousa, Samavati and Jorge
// 2006, "Modeling plant structures using concept sketches", sections 3-4):
// the construction lines of a drawing and its lateral organ strokes, read
// into a plant structure (this file), from which concept_plant.h builds the
// 3D plant.
//
// A drawing's strokes of role `construction` (sketch/drawing.h; role
// `branch`, an unlabelled open line, counts as construction when a drawing
// has none) are told apart as follows, the first rule that applies:
//   1. by name: a word of the stroke's SVG id, inkscape:label or class (or
//      its layer's) "stem", "boundary"/"boundaries"/"envelope", or
//      "inclination"/"inclinations";
//   2. a closed construction stroke is a boundary (an envelope drawn round);
//   3. by geometry, over the open strokes: a stroke is lengthwise when its
//      bounding box is at least as tall as it is wide. The stem is the
//      lengthwise stroke in the middle (the median of their mean x; of two,
//      the one nearer the middle of the transverse strokes); the other
//      lengthwise strokes are boundaries. A transverse stroke that crosses
//      the stem (extended by kInclinationReach of its length at each end)
//      is an inclination line, any other a boundary piece.
// The stem runs from its base (the end nearer the drawing's root circle, or
// else the lower end) to its tip. At least a stem and a boundary are needed;
// inclination lines are optional (without them organs leave the stem at
// ConceptPlantOptions::default_branching_deg).
//
// Organ strokes (role `organ`; without any, `crown` strokes, which is what
// unlabelled closed shapes are): each closed one is the outline of a blade
// (leaf, petal) seen from above, each open one a thin organ (needle,
// branch) drawn as its centre line. The organ's reference line (paper,
// section 7: P0 P1) joins its base to its tip: for an outline the two
// points farthest apart, for a line its two ends; the base is the end
// nearer the stem when one lies within half the organ's length of it, else
// the lower end. The first two organs of the kind used (blades if any are
// drawn, else lines) are the paper's two templates, between which every
// placed organ is interpolated (section 4.2).
//
// The phyllotactic pattern may be written in the drawing: a <text> or a
// stroke name holding one of the pattern names (ConceptPatternFromName).
#ifndef SYLVA_SKETCH_CONCEPT_SKETCH_H_
#define SYLVA_SKETCH_CONCEPT_SKETCH_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "sketch/drawing.h"

namespace sylva {

// Anastacio et al. 2006, section 5: one organ per node, each node turned by
// the divergence angle from the previous one (Yotsumoto 1993).
enum class ConceptPattern { kSpiral, kMonostichous, kDistichous, kTristichous, kTetrastichous };

const char* ConceptPatternName(ConceptPattern pattern);
// "spiral", "monostichous", "distichous", "tristichous", "tetrastichous"
// (case-insensitive); nullopt for anything else.
std::optional<ConceptPattern> ConceptPatternFromName(const std::string& name);
// The paper's divergence angles, degrees: spiral 137.5 (the golden angle),
// monostichous 30, distichous 180, tristichous 120, tetrastichous 90.
double ConceptDivergenceDeg(ConceptPattern pattern);

// A transverse stroke is an inclination line if it crosses the stem when
// extended by this fraction of its length at each end (hand-drawn lines
// often stop short of the stem).
inline constexpr double kInclinationReach = 0.1;

// One drawn organ in its own frame, in units of its reference line's length:
// u from the base (0) to the tip (1) along the reference line, v across it
// (to the left of base -> tip on the canvas), at `kOrganStations` evenly
// spaced u.
struct ConceptOrganTemplate {
  bool blade = true;  // an outline; false: a line organ (needle, branch)
  // Blade: half widths to either side of the reference line at each station
  // (>= 0; 0 at both ends).
  std::vector<double> left, right;
  // Line: the drawn centre line (u, v) at kOrganStations points evenly
  // spaced along it, from (0, 0) to (1, 0).
  std::vector<Eigen::Vector2d> centre;
  double length_px = 0.0;  // the reference line's length on the canvas
};
inline constexpr int kOrganStations = 17;

// The interpretation of a concept drawing, in canvas pixels (x right, y down).
struct ConceptStructure {
  std::string source;                 // the drawing's file, for messages
  std::vector<Eigen::Vector2d> stem;  // base first
  double stem_width_px = 0.0;         // drawn stroke width; 0 = unknown
  // The envelope: the boundary strokes (closed ones closed), plus segments
  // joining each boundary's ends to the nearer stem end (so that every ray
  // from the stem meets it).
  std::vector<std::vector<Eigen::Vector2d>> envelope;
  int num_boundaries = 0;  // boundary strokes drawn
  // Inclination lines as drawn, ordered from the stem's tip to its base,
  // each with where it crosses the stem (arc length from the base, px) and
  // its branching angles to the left and right of the stem (paper 6.2:
  // alpha_i, beta_i, degrees from the stem's downward direction).
  struct Inclination {
    std::vector<Eigen::Vector2d> points;
    double stem_arc_px = 0.0;
    double left_deg = 90.0, right_deg = 90.0;
  };
  std::vector<Inclination> inclinations;
  std::vector<ConceptOrganTemplate> organs;  // the templates (at most 2)
  std::optional<ConceptPattern> drawn_pattern;
  std::string BriefReport() const;
};

// Throws InputError naming drawing.source when there is no stem, no
// boundary, or a line is degenerate (zero length).
ConceptStructure InterpretConceptDrawing(const SketchDrawing& drawing);

// Geometry on the canvas shared with concept_plant.cc and tests.
double PolylineLengthPx(const std::vector<Eigen::Vector2d>& points);
// The point at arc length `s` (clamped) and its unit tangent.
Eigen::Vector2d PointAtArc(const std::vector<Eigen::Vector2d>& points, double s,
                           Eigen::Vector2d* tangent = nullptr);
// The smallest t > 0 with origin + t direction on one of `polylines`
// (closed ones are not closed here: closing segments are listed points);
// +inf if none.
double CastRay2d(const std::vector<std::vector<Eigen::Vector2d>>& polylines,
                 const Eigen::Vector2d& origin, const Eigen::Vector2d& direction);

}  // namespace sylva

#endif  // SYLVA_SKETCH_CONCEPT_SKETCH_H_
