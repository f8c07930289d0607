// 3D gestures (issue 17, Murakami et al.): the paths of a tracked stylus or
// hand, each a stroke of timed 3D samples with a kind saying what it draws.
// A `trunk` stroke draws a trunk or main branch (section 4.1: the first one
// is the trunk, later ones join it where they start); an `roi` stroke draws
// one side of the silhouette of the region of interest the L-system grows
// in (section 4.2). Units are the file's (sylva treats them as metres), up
// = +Z.
//
// Readers (ReadGesture picks one by extension), each validating: a bad file
// throws one InputError naming the file and the line, sample or JSON
// location at fault.
//
//  - `.json`: sylva's own format,
//      {"format": "sylva-gesture", "version": 1,
//       "strokes": [{"kind": "trunk" | "roi",
//                    "samples": [[t, x, y, z], [t, x, y, z, pressure], ...]}]}
//    t in seconds, strictly increasing within a stroke; pressure in [0, 1],
//    optional per sample (default 1). Unknown keys are ignored.
//  - `.inkml`: W3C InkML (https://www.w3.org/TR/InkML/). The <traceFormat>
//    (inside <ink> or <definitions>/<context>) declares the channel order;
//    it must have X, Y and Z, may have T (time) and F (force: pressure).
//    Each <trace> is a stroke (also inside <traceGroup>s); it is an ROI
//    stroke when its xml:id, its brushRef or its <traceGroup>'s xml:id
//    starts with "roi", or it holds <annotation type="kind">roi</annotation>;
//    otherwise a trunk stroke. Samples are comma-separated, values
//    space-separated; explicit values only (the ' " ! ? difference
//    encodings are refused). Without T, samples are timed by arc length.
//  - `.obj`: `v x y z` vertices and `l i j k ...` polylines (1-based or
//    negative indices); a polyline in a group or object named `roi...` is an
//    ROI stroke, others trunk strokes. No time: samples are timed by arc
//    length (constant speed).
//  - `.ply`: ASCII PLY with `element vertex` (x, y, z) and `element edge`
//    (vertex1, vertex2); edges are chained into polylines at vertices of
//    degree 2. All strokes are trunk strokes unless the vertices have an
//    int property `roi` (1 = ROI). No time, as for OBJ.
#ifndef SYLVA_SKETCH_GESTURE_IO_H_
#define SYLVA_SKETCH_GESTURE_IO_H_

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

enum class GestureKind { kTrunk, kRoi };

struct GestureSample {
  double t = 0.0;                                      // seconds (or arc length if untimed)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world units, up = +Z
  double pressure = 1.0;                               // [0, 1]
};

struct GestureStroke {
  GestureKind kind = GestureKind::kTrunk;
  std::vector<GestureSample> samples;  // t strictly increasing
  double Length() const;               // arc length of the positions
};

struct GestureSet {
  std::string source;  // the file, for messages
  std::vector<GestureStroke> strokes;
  // Whether the samples carry real time (JSON, InkML with T) or only arc
  // length (OBJ, PLY, InkML without T): speed is then constant.
  bool timed = false;

  int Count(GestureKind kind) const;
  // Throws InputError naming `source`: no stroke, a stroke with fewer than
  // two distinct samples, non-finite values or time not increasing.
  void Check() const;
};

std::string GestureKindName(GestureKind kind);

GestureSet ReadGestureJson(const std::filesystem::path& path);
GestureSet ReadGestureInkml(const std::filesystem::path& path);
GestureSet ReadGestureObj(const std::filesystem::path& path);
GestureSet ReadGesturePly(const std::filesystem::path& path);
// By extension (.json, .inkml, .obj, .ply); throws InputError otherwise.
GestureSet ReadGesture(const std::filesystem::path& path);

// Writes `gestures` as sylva-gesture JSON (atomically).
void WriteGestureJson(const std::filesystem::path& path, const GestureSet& gestures);

}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_IO_H_
