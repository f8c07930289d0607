// Internal to sketch/: what the traced centre lines of a scan stand for
// (scan_tracing.h, steps 5 and 6): trunks drawn as two outlines, and the
// crown outline.
#ifndef SYLVA_SKETCH_SCAN_INTERPRET_H_
#define SYLVA_SKETCH_SCAN_INTERPRET_H_

#include <opencv2/core.hpp>
#include <vector>

#include "sketch/drawing.h"
#include "sketch/scan_skeleton.h"

namespace sylva::scan {

// A centre line with its interpretation. Points in pixel coordinates (pixel
// centres at integers), as in SkeletonEdge.
struct TracedStroke {
  SkeletonEdge edge;   // node ids -1 where a stroke was cut
  double width = 0.0;  // pixels
  StrokeRole role = StrokeRole::kBranch;
  bool trunk_pair = false;  // the middle of a trunk drawn as two outlines
};

struct TrunkPairOptions {
  double line_width_px = 1.0;
  double min_separation_px = 2.0;
  double max_separation_px = 50.0;
  double max_angle_rad = 0.35;
  double min_length_separations = 2.0;
  // A trunk reaches the ground: the pair's lowest point must lie below
  // this (pixels, y down).
  double min_base_y_px = 0.0;
};

// Replaces outline pairs with paper between them (`ink`: CV_8U, non-zero =
// ink) by their middle line (role branch, width = their distance); returns
// the number of pairs merged.
int MergeTrunkPairs(const cv::Mat& ink, const TrunkPairOptions& options,
                    std::vector<TracedStroke>& strokes);

struct CrownOptions {
  double line_width_px = 1.0;
  double min_area_fraction = 0.02;
  double on_outline_fraction = 0.6;
};

// Finds the crown outlines of `ink` (CV_8U, non-zero = ink) and replaces
// the strokes lying on each by one closed crown stroke along the outline's
// centre line. Trunk-pair strokes are never crown strokes, and the area
// between a pair is no part of a crown.
void MarkCrownStrokes(const cv::Mat& ink, const CrownOptions& options,
                      std::vector<TracedStroke>& strokes);

}  // namespace sylva::scan

#endif  // SYLVA_SKETCH_SCAN_INTERPRET_H_
