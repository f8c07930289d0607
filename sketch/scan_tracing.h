// Scanned or photographed pencil drawings of trees -> strokes (issue 14,
// item 1): the raster reader of the sketch modes.
//
//   ScanTracingSummary summary;
//   SketchDrawing drawing = TraceScannedDrawing("maple.png", ScanTracingOptions(), &summary);
//
// The steps:
//   1. Binarise with Sauvola's local threshold (Sauvola & Pietikainen 2000,
//      T = m (1 + k (s / R - 1)), R = 128 grey levels, OpenCV ximgproc): the
//      threshold follows the local mean m and standard deviation s, so a scan
//      darker at one side or a photo of a page in uneven light keeps its
//      faint lines and loses its shading. A window as wide as a few strokes
//      (a fraction of the page, not a pixel count) follows the light without
//      eating thick lines. Ink blobs smaller than a stroke of spur length are
//      dust and dropped.
//   2. Thin to one-pixel centre lines (Zhang & Suen 1984).
//   3. Trace: end points (crossing number 1) and junctions (crossing number
//      >= 3, pixels within junction_cluster_widths one node) are the nodes; the
//      pixel chains between them are strokes. Spurs (end point to junction)
//      shorter than spur_length_widths line widths are pruned: a brush blob
//      or a corner leaves them. Stroke ends closer than gap_length_widths
//      line widths that point at each other are joined: a pencil line that
//      skipped. Strokes are simplified by Douglas-Peucker.
//   4. Width: each stroke's line width is 2 d - 1 for the median d of the
//      ink's distance transform (pixels to the nearest paper pixel) along its
//      centre line, away from junctions.
//   5. Trunks drawn as two outlines: two centre lines (two strokes, or the
//      two arms of one U-shaped stroke closed at the bottom) that run side by
//      side -- at each sample of one, a sample of the other lies across it
//      (within trunk_max_angle_deg of the normal), nearly parallel (the same
//      angle), trunk_min_separation_widths line widths to
//      trunk_max_separation_fraction of the drawing's size apart, with paper
//      between them -- for at least trunk_min_length_separations times their
//      separation, and reaching down to the drawing's base
//      (trunk_max_base_height_fraction), become one branch stroke along their
//      middle whose width is their distance (centre line to centre line).
//      What is left of the two outlines beyond the pair is kept if longer
//      than twice their separation (a U's bottom cap is not).
//   6. Crown outline vs branches: the paper regions the ink encloses (not
//      reaching the page's edge) larger than crown_min_area_fraction of the
//      ink's bounding box are the crown's inside, with the smaller enclosed
//      pockets that lie more next to them than next to the open paper (where
//      a branch touches the outline from inside; not the gap of a fork below
//      the crown), merged across the strokes between them (a closing by two
//      line widths), without the inside of trunk pairs. The outer boundary of
//      each such part, grown by half a line width, runs along the centre of
//      the drawn outline. A stroke at least crown_on_outline_fraction of
//      whose points lie within a line width of it is part of it: the strokes
//      of each outline that has any are replaced by one closed crown stroke
//      along it (width: theirs). Everything else is a branch. So a tree
//      drawn as a closed cloud with branches inside gives one closed crown
//      whatever touches or splits its outline; a crown drawn open (not
//      enclosing paper) is not a crown, and a tiered crown whose tiers do not
//      touch gives one crown per tier.
//   The root is the lowest end of the trunk drawn as two outlines, if there
//   is one, else of the branch strokes.
// Coordinates are canvas pixels (drawing.h): pixel centres at +0.5.
#ifndef SYLVA_SKETCH_SCAN_TRACING_H_
#define SYLVA_SKETCH_SCAN_TRACING_H_

#include <filesystem>
#include <string>

#include "core/types/float_image.h"
#include "sketch/drawing.h"

namespace sylva {

struct ScanTracingOptions {
  // Sauvola's window side as a fraction of the image's shorter side (rounded
  // to an odd pixel count, at least 15 px). 0.05 is 31 px on a 608 px sketch:
  // about six 5 px strokes across.
  double sauvola_window_fraction = 0.05;
  // Sauvola's k (dimensionless, > 0): how far below the local mean, relative
  // to the local contrast, ink must be. 0.2 keeps light pencil; 0.5 (the
  // paper's value for printed text) drops it.
  double sauvola_k = 0.2;
  // A page whose darkest pixels are less than this (grey, 0 = black, 1 =
  // white) below its median has no ink: blank.
  double min_ink_contrast = 0.15;
  // Junction pixels closer than this many line widths (at least 2 px) are
  // one junction: two lines crossing leave two three-way junction pixels up
  // to about a line width apart, which are one four-way junction.
  double junction_cluster_widths = 1.5;
  // Douglas-Peucker tolerance of the output strokes (pixels).
  double simplify_tolerance_px = 1.0;
  // Spurs and isolated strokes shorter than this many line widths go.
  double spur_length_widths = 3.0;
  // Stroke ends at most this many line widths apart are joined ...
  double gap_length_widths = 4.0;
  // ... if each end points at the other within this angle (degrees).
  double gap_max_angle_deg = 30.0;
  // Trunk outline pairs: centre lines at least this many line widths apart,
  double trunk_min_separation_widths = 1.5;
  // at most this fraction of the ink's bounding-box size (the larger side),
  double trunk_max_separation_fraction = 0.08;
  // parallel (and across each other) within this angle (degrees),
  double trunk_max_angle_deg = 20.0;
  // for at least this many times their separation along the lines,
  double trunk_min_length_separations = 2.0;
  // reaching down to the drawing's base: their lowest point at most this
  // fraction of the ink's bounding-box height above the ink's lowest point.
  // (Branches drawn as outline pairs higher up stay two strokes: parallel
  // fronds and needles, which hand sketches are full of, look the same.)
  double trunk_max_base_height_fraction = 0.15;
  // Enclosed paper regions this large (fraction of the ink's bounding-box
  // area) are the inside of a crown.
  double crown_min_area_fraction = 0.02;
  // A stroke is a crown stroke if at least this fraction of it lies on a
  // crown outline.
  double crown_on_outline_fraction = 0.6;

  // Throws InputError naming the first option out of range.
  void Check() const;
};

struct ScanTracingSummary {
  int width_px = 0, height_px = 0;
  double ink_fraction = 0;   // of the page's pixels
  double line_width_px = 0;  // median over the centre lines
  int junctions = 0;         // nodes where three or more strokes meet
  int end_points = 0;        // stroke ends not at a junction
  int spurs_pruned = 0;
  int gaps_closed = 0;
  int trunk_pairs = 0;    // outline pairs merged into one branch
  int crown_strokes = 0;  // strokes with role crown (closed or not)
  int closed_crowns = 0;  // of which closed
  int branch_strokes = 0;
  // Seconds per step.
  double binarise_s = 0, thin_s = 0, trace_s = 0, interpret_s = 0;
  std::string BriefReport() const;
};

// Reads `image` (PNG, JPEG, TIFF, ... through core/io/image_io.h; colour is
// averaged to grey, alpha composited over white paper) and traces it.
// InputError naming the file if it cannot be read or holds no drawing (a
// blank page), or naming the option if `options` fail Check().
SketchDrawing TraceScannedDrawing(const std::filesystem::path& image,
                                  const ScanTracingOptions& options,
                                  ScanTracingSummary* summary = nullptr);

// The same on a grey image already in memory: one channel, 0 = black ink, 1
// = white paper. `source` names it in errors and in SketchDrawing::source.
SketchDrawing TraceScannedDrawing(const FloatImage& grey, const std::string& source,
                                  const ScanTracingOptions& options,
                                  ScanTracingSummary* summary = nullptr);

}  // namespace sylva

#endif  // SYLVA_SKETCH_SCAN_TRACING_H_
