// Strokes a person draws on a photo to give the trunk and main branches
// (thesis 3.2.2: "the user can provide the information as a manually
// sketched graph"). GraphFromStrokes (stroke_graph.h) turns them into the
// photo's attractor graph. In a project they live beside the photo as
// edits/<photo>.strokes.svg or edits/<photo>.strokes.json.
//
// Coordinates are the photo's pixels: x to the right, y down, the image
// covering [0, width] x [0, height] (so pixel (i, j)'s centre is at
// (i + 0.5, j + 0.5), COLMAP's convention).
//
// SVG files (what Inkscape and most drawing programs save). The typical use:
// open the photo in Inkscape (File > Open, so the document has the photo's
// size), draw the trunk and branches with the pen or pencil tool on a layer,
// optionally put a small circle with id "root" on the tree base, save:
//
//   <svg xmlns="http://www.w3.org/2000/svg" width="1440" height="1080"
//        viewBox="0 0 1440 1080">
//     <image href="IMG_0001.jpg" width="1440" height="1080"/>    <!-- ignored -->
//     <g id="layer1" transform="translate(0, 2)">
//       <path d="M 720 1050 C 722 900 700 700 718 560"/>            <!-- trunk -->
//       <path d="M 718 560 q 60 -80 150 -160"/>                     <!-- a branch -->
//       <polyline points="718,560 640,420 600,300"/>                <!-- another -->
//       <circle id="root" cx="720" cy="1048" r="6"/>               <!-- tree base -->
//     </g>
//   </svg>
//
//   - Strokes: every <path> (each subpath is one stroke; all commands M L H V
//     C S Q T A Z, absolute and relative), <polyline>, <polygon> (closed) and
//     <line>. Curves and arcs are flattened to polylines that stay within a
//     quarter pixel of the exact curve (in photo pixels). Fill and stroke
//     styles are ignored.
//   - Transforms: the `transform` attribute of shapes and of enclosing <g>,
//     <a> and nested <svg> elements (matrix, translate, scale, rotate, skewX,
//     skewY). A nested <svg>'s own viewport (x, y, viewBox) is ignored.
//   - Skipped: elements with display="none" (or style "display:none", e.g.
//     a hidden Inkscape layer) and everything inside them; <image>, <text>,
//     <defs>, <symbol>, <clipPath>, <mask>, <marker>, <pattern>, <use>,
//     metadata and any element not named here.
//   - The root point: a <circle> with id "root" or class "root" (its centre);
//     other circles are ignored. At most one.
//   - Mapping to the photo: the root <svg>'s viewBox (min-x, min-y, width,
//     height) is stretched onto [0, photo width] x [0, photo height], x and y
//     independently (preserveAspectRatio is ignored: the drawing is assumed
//     to cover exactly the photo). Without a viewBox, its width and height
//     (px, mm, cm, in, pt, pc; 96 px per inch) are stretched the same way; with
//     neither (or percentages), user units are photo pixels.
//
// JSON files (what a program writes):
//   {"format": "sylva-strokes", "version": 1, "width": 1440, "height": 1080,
//    "strokes": [[[720, 1050], [718, 560]], [[718, 560], [868, 400]]],
//    "root": [720, 1048]}                                          // optional
// Each stroke is a list of [x, y] points; width and height are the size of
// the image the points were drawn on: if they differ from the photo's, x is
// scaled by photo width / width and y by photo height / height.
//
// Either reader throws one InputError naming the file and the problem (with
// the element and its line, or the JSON location) for a file that is not XML
// or JSON, bad path or transform syntax, a number that is not a number or not
// finite, no strokes, a stroke with fewer than two distinct points, a wrong
// format or version.
#ifndef SYLVA_SKETCH_STROKES_H_
#define SYLVA_SKETCH_STROKES_H_

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

struct Stroke {
  // The drawn polyline in photo pixels, in drawing order.
  std::vector<Eigen::Vector2d> points;
};

struct StrokeSet {
  // The photo's size in pixels.
  int width = 0;
  int height = 0;
  std::vector<Stroke> strokes;
  // The tree base (or the first branching on the trunk) if the person gave
  // one, in photo pixels.
  std::optional<Eigen::Vector2d> root;

  // Whether p lies within the photo extended by its own size on every side
  // ([-width, 2 width] x [-height, 2 height]). Points beyond that mean a
  // broken file or a drawing made for another photo (false for NaN).
  bool NearPhoto(const Eigen::Vector2d& p) const;

  // Throws InputError naming `source_name` if the size is not positive,
  // there are no strokes, a stroke has fewer than 2 points or two equal
  // consecutive points, or a point (or the root) is not NearPhoto.
  void Check(const std::string& source_name) const;
};

// The readers take the size of the photo the strokes belong to (> 0).
StrokeSet ReadStrokesSvg(const std::filesystem::path& path, int photo_width, int photo_height);
StrokeSet ReadStrokesJson(const std::filesystem::path& path, int photo_width, int photo_height);
// By extension (case-insensitive): .svg or .json; anything else is an InputError.
StrokeSet ReadStrokes(const std::filesystem::path& path, int photo_width, int photo_height);

// Writes the JSON form atomically (what ReadStrokesJson reads back exactly).
// Throws Error if the set fails Check().
void WriteStrokesJson(const std::filesystem::path& path, const StrokeSet& strokes);

}  // namespace sylva

#endif  // SYLVA_SKETCH_STROKES_H_
