// A drawing of a tree as the sketch modes read it (issue 14): strokes on a
// canvas, each with the role it plays, whatever file it came from (an
// Inkscape SVG, a scanned pencil drawing traced into centre lines, a
// Quick, Draw! doodle). The sketch modes turn drawings into density (crown
// outlines) and attractors (branch strokes); several drawings of one tree
// are its views (front, side), each its own file.
//
// Coordinates are canvas pixels: x to the right, y down, the canvas covering
// [0, width] x [0, height] (the convention of strokes.h and of the photos).
#ifndef SYLVA_SKETCH_DRAWING_H_
#define SYLVA_SKETCH_DRAWING_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

// What a stroke stands for.
enum class StrokeRole {
  kBranch,        // a branch's centre line (the trunk included)
  kCrown,         // (part of) the crown's outline
  kConstruction,  // Anastacio 2006: stem, boundary or inclination line
  kOrgan,         // Anastacio 2006: a lateral organ (leaf, flower, branch)
};

// "branch", "crown", "construction", "organ".
const char* StrokeRoleName(StrokeRole role);
// The role named `name` (case-insensitive, as above); nullopt if none.
std::optional<StrokeRole> StrokeRoleFromName(const std::string& name);

struct SketchStroke {
  // The drawn polyline in canvas pixels, in drawing order (for a closed
  // outline the last point is not repeated).
  std::vector<Eigen::Vector2d> points;
  StrokeRole role = StrokeRole::kBranch;
  bool closed = false;
  // How thick the stroke was drawn, in canvas pixels (SVG stroke-width
  // through the transforms; for a traced scan the line's width, or for a
  // trunk drawn as two outline lines the distance between them); 0 =
  // unknown. A cue for branch radii, never a measurement.
  double width = 0.0;
  // Lower-case words naming the stroke in an SVG: the element's id and the
  // inkscape:label and class words of the element and then of its
  // ancestors, nearest first, space-separated ("stem construction"); empty
  // for other inputs. Lets a
  // mode tell strokes of one role apart (sketch/concept_sketch.h).
  std::string name;
};

struct SketchDrawing {
  // Where it was read from (named in errors and in the report).
  std::string source;
  // The canvas size in pixels (> 0).
  double width = 0.0;
  double height = 0.0;
  std::vector<SketchStroke> strokes;
  // The tree base if the drawing marks one, in canvas pixels.
  std::optional<Eigen::Vector2d> root;
  // The text of visible SVG <text> elements (annotations such as a
  // phyllotaxis pattern), one entry per element, trimmed.
  std::vector<std::string> texts;
  // How the reader read what the drawing does not say (e.g. an outline
  // joined from open pieces), one sentence each, for the user.
  std::vector<std::string> notes;

  int CountRole(StrokeRole role) const;
  // Throws InputError naming `source` if the canvas size is not positive and
  // finite, there are no strokes, a stroke has fewer than 2 points (3 if
  // closed), a point is not finite or lies farther than the canvas size
  // outside the canvas.
  void Check() const;
};

}  // namespace sylva

#endif  // SYLVA_SKETCH_DRAWING_H_
