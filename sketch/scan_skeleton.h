// Internal to sketch/ (and its benchmark): the centre-line steps of
// scan_tracing.h on OpenCV images. A binary ink image is thinned to a
// one-pixel skeleton, and the skeleton is traced into a graph whose nodes are
// junctions and end points and whose edges are the pixel chains between them;
// the graph is then cleaned (spurs pruned, gaps closed, chains merged through
// two-way nodes). Images are CV_8U, 0 = paper, non-zero = ink.
#ifndef SYLVA_SKETCH_SCAN_SKELETON_H_
#define SYLVA_SKETCH_SCAN_SKELETON_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace sylva::scan {

// Sauvola's threshold T = m (1 + k (s / R - 1)) from the mean m and standard
// deviation s of the grey levels (CV_8U) in a `window` x `window` box
// (borders replicated, sums in float); 255 on ink (grey <= T), 0 on paper.
// The same result as cv::ximgproc::niBlackThreshold(BINARIZATION_SAUVOLA,
// THRESH_BINARY_INV), whose module is not linked (core/util/thinning.h).
cv::Mat SauvolaInk(const cv::Mat& grey, int window, double k, double range);

// Zhang & Suen 1984 thinning (core/util/thinning.h), the same result as
// cv::ximgproc::thinning(ink, THINNING_ZHANGSUEN) (the image's border pixels
// are never removed), but each sub-iteration visits only the pixels on the
// ink's current boundary instead of the whole image: the cost follows the
// ink's area, not the page's. Returns 255 on the skeleton, 0 elsewhere.
cv::Mat ThinZhangSuen(const cv::Mat& ink);

struct SkeletonNode {
  Eigen::Vector2d position;  // pixel coordinates (pixel centres at integers)
  bool junction = false;     // three or more branches met here; else an end point
};

struct SkeletonEdge {
  int node_a = -1;  // -1 for both ends of a closed loop without nodes
  int node_b = -1;
  // From node_a's position to node_b's, through the chain's pixel centres
  // (for a closed loop the last point is not repeated).
  std::vector<Eigen::Vector2d> points;
  bool closed = false;
};

struct SkeletonGraph {
  std::vector<SkeletonNode> nodes;
  std::vector<SkeletonEdge> edges;
  // The number of edges ending at each node (a closed loop through a node
  // counts twice).
  std::vector<int> Degrees() const;
};

// The skeleton's graph. A pixel is an end point when its crossing number
// (the 0 -> 1 transitions around its 8 neighbours) is 1 and a junction pixel
// when it is 3 or more; junction pixels closer than `junction_cluster_px`
// (Euclidean) are one junction node at their centroid. Skeleton cycles
// without nodes become closed loops; isolated pixels are ignored.
SkeletonGraph TraceSkeleton(const cv::Mat& skeleton, double junction_cluster_px);

// Polyline length in pixels (closed loops include the closing segment).
double EdgeLength(const SkeletonEdge& edge);

// Removes edges from an end point to a junction shorter than `min_length_px`
// (drawing noise, brush blobs) and isolated edges (end point to end point)
// shorter than it; then merges chains through nodes left with two edges.
// Returns the number of edges removed.
int PruneSpurs(double min_length_px, SkeletonGraph& graph);

// Joins pairs of end points closer than `max_gap_px` whose strokes point at
// each other (each end's direction within `max_angle_rad` of the line to the
// other end), nearest pairs first; an end joins at most once. Returns the
// number of gaps closed.
int CloseGaps(double max_gap_px, double max_angle_rad, SkeletonGraph& graph);

// Concatenates edges through every node with exactly two edge ends, and
// drops nodes no edge uses any more (renumbering the rest).
void MergeThroughTwoWayNodes(SkeletonGraph& graph);

}  // namespace sylva::scan

#endif  // SYLVA_SKETCH_SCAN_SKELETON_H_
