// Readers of drawings of trees (issue 14, sketch input): vector files whose
// strokes already are polylines. Each returns a SketchDrawing (drawing.h)
// that passed Check(), or throws one InputError naming the file and what is
// wrong where (the element and its line, or the ndjson line); never a
// partial drawing.
//
// SVG as drawn in Inkscape (ReadSketchSvg)
// ----------------------------------------
//   <svg xmlns="http://www.w3.org/2000/svg"
//        xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
//        width="200mm" height="300mm" viewBox="0 0 200 300">
//     <g inkscape:groupmode="layer" inkscape:label="Crown">
//       <ellipse cx="100" cy="90" rx="80" ry="70"/>                <!-- crown -->
//     </g>
//     <g inkscape:label="branches" style="stroke:#6b4226;stroke-width:4">
//       <path d="M 100 290 C 102 200 98 150 100 120"/>             <!-- branch -->
//     </g>
//     <path d="M 40 60 q 20 -30 50 -20" stroke="green"/>            <!-- crown -->
//     <circle id="root" cx="100" cy="292" r="3"/>                  <!-- root -->
//   </svg>
//
//   - Geometry as for strokes on photos (strokes.h, the same code): every
//     <path> subpath, <polyline>, <polygon>, <line>, and here also <rect>
//     (rounded corners ignored), <circle> and <ellipse>; transforms of shapes
//     and of enclosing <g>, <a>, <svg>; hidden elements, <defs>, <image>,
//     <text>, ... skipped; curves flattened to within 0.25 canvas pixels.
//   - Canvas: the root's viewBox size (one user unit = one canvas pixel, the
//     viewBox's min-x, min-y at the canvas origin), else its width and height
//     (px, mm, cm, in, pt, pc at 96 px per inch, user units = CSS px). With
//     neither, the canvas size is unknown: an InputError.
//   - Closed: <polygon>, <rect>, <circle>, <ellipse> and subpaths that end
//     where they start (Z, or drawn back to the start). Closed strokes keep
//     closed = true and do not repeat their first point.
//   - Role, the first rule that applies:
//       1. the nearest `inkscape:label` or `class` word, on the element or an
//          ancestor (a layer), that names a role: crown, branch, construction,
//          organ, or their plurals, case-insensitive ("Crown", "branches");
//       2. a closed shape is a crown outline;
//       3. its colour, the stroke colour (or, without a stroke, the fill
//          colour; #rgb, #rrggbb, rgb(), common names): green-ish (hue
//          75-165 degrees, HSV saturation >= 0.2, value >= 0.1) is a crown
//          stroke, any other colour (brown, black, grey, ...) a branch;
//       4. a branch.
//   - Width: `stroke-width` (attribute or style, inherited from ancestors)
//     times the transform's scale (the square root of its linear part's
//     determinant); 0 (unknown) if not given or the stroke is "none".
//   - Root: a <circle> with id or class "root" gives SketchDrawing::root (its
//     centre) and is not a stroke. At most one.
//   - Names and notes: a stroke's id, inkscape:label and class words and its
//     ancestors' become SketchStroke::name (the concept sketch mode tells
//     stem, boundary and inclination lines apart by them); the text of each
//     visible <text> element is one of SketchDrawing::texts.
//
// Google's Quick, Draw! simplified ndjson (ReadQuickDrawNdjson)
// ------------------------------------------------------------
//   One drawing per line: {"word": "tree", ..., "drawing": [[[x0, x1, ...],
//   [y0, y1, ...]], ...]}, coordinates 0-255, y down. The canvas is
//   256 x 256. Strokes of a single point (dots) are skipped; consecutive
//   repeated points are merged. A Quick, Draw! tree is usually a trunk plus
//   a cloud-shaped crown, so a stroke is a crown outline when
//     - it encloses at least 10 % of the drawing's bounding box (the area of
//       the polygon closed by the chord from its end to its start), and
//     - it does not stand on the ground (reach the lowest 5 % of the
//       drawing's height) below a stroke that starts higher (that is a trunk
//       drawn as an outline), and
//     - it is nearly closed (its end within 10 % of its length of its start;
//       then closed = true) or at least 75 % of its points lie above the top
//       of the strokes that stand on the ground (plus 5 % of the drawing's
//       height; a cloud open where the trunk enters).
//   When no stroke is a crown outline, the drawing may be one outline drawn
//   in pieces (a conifer, or trunk and crown as one silhouette, left open at
//   the ground and between strokes): the strokes are chained end to end,
//   from the lowest stroke end, each time to the stroke whose nearer end is
//   closest to the chain's end (within 40 % of the drawing's larger side).
//   If the chain, closed by the chord back to its start (along the ground),
//   encloses at least 25 % of the drawing's bounding box, holds at least
//   60 % of the drawing's ink and is at least a quarter as wide as it is
//   tall (two trunk lines are not a crown), it becomes one closed crown
//   outline in place of its pieces.
//   Every other stroke is a branch.
#ifndef SYLVA_SKETCH_DRAWING_IO_H_
#define SYLVA_SKETCH_DRAWING_IO_H_

#include <filesystem>

#include "sketch/drawing.h"

namespace sylva {

// An SVG drawing (see above).
SketchDrawing ReadSketchSvg(const std::filesystem::path& path);

// Drawing `index` (0-based line number, blank lines counted) of a Quick,
// Draw! simplified ndjson file; an InputError naming the file if `index` is
// out of range or the line is not a valid drawing.
SketchDrawing ReadQuickDrawNdjson(const std::filesystem::path& path, int index);

// Writes `drawing` (which must pass Check()) as an SVG that ReadSketchSvg
// reads back with the same strokes: the canvas as the viewBox, one layer
// per role (inkscape:label "crown", "branch", ...), each stroke a
// <polyline> (or a <polygon> if closed) with its width as stroke-width,
// the root as <circle id="root">. Coordinates are written with 9
// significant digits. Atomic.
void WriteSketchSvg(const std::filesystem::path& path, const SketchDrawing& drawing);

// By extension (case-insensitive): .svg (ReadSketchSvg, `index` ignored),
// .ndjson (ReadQuickDrawNdjson), or a scanned or photographed drawing .png,
// .jpg, .jpeg, .tif, .tiff (TraceScannedDrawing with the default
// ScanTracingOptions); any other is an InputError naming the accepted
// extensions.
SketchDrawing ReadSketch(const std::filesystem::path& path, int index = 0);

}  // namespace sylva

#endif  // SYLVA_SKETCH_DRAWING_IO_H_
