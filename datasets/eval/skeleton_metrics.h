// How far a reconstructed 3D skeleton is from a true one: how much wood it
// carries (total length), how much of it lies on a true branch (precision),
// how much of the true tree it finds (recall), the Chamfer distance, and the
// branch axes per order. Lengths are measured along the edges, so the
// figures do not depend on how densely either skeleton is noded.
#ifndef SYLVA_DATASETS_EVAL_SKELETON_METRICS_H_
#define SYLVA_DATASETS_EVAL_SKELETON_METRICS_H_

#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

struct SkeletonComparisonOptions {
  // A stretch of one skeleton "lies on" the other if it is within this
  // fraction of the tree's height of it (issue 12: 2 %).
  double tolerance_fraction = 0.02;
  // Both skeletons are sampled this often along their edges, as a fraction
  // of the height (well under the tolerance).
  double spacing_fraction = 0.002;
  // Wood traced twice: a stretch within this fraction of the height of the
  // same skeleton's wood elsewhere, more than 3 times as far away along the
  // skeleton (so not the same branch, nor a fork's first stretch); of each
  // such pair the stretch carrying fewer strands (ties: the later node)
  // counts. Forks narrower than about 40 degrees count about a radius of
  // their thinner branch. 0 skips the figure.
  double duplicate_fraction = 0.01;
};

// The length of `skeleton` that runs beside its own wood (see
// SkeletonComparisonOptions::duplicate_fraction), world units: what a
// skeleton would lose if every branch traced twice were traced once.
// `radius` and `spacing` in world units (spacing well under radius).
double DuplicatedLength(const SkeletonGraph& skeleton, double radius, double spacing);

// Branch axes (SkeletonGraph::BranchAxes) of one order.
struct OrderFigures {
  int axes = 0;
  double length = 0.0;  // summed along the axes' edges (junction excluded), world units
};

struct SkeletonComparison {
  double height = 0.0;            // the reference height used (world units)
  double length = 0.0;            // total edge length of the reconstruction
  double true_length = 0.0;       // total edge length of the truth
  double length_ratio = 0.0;      // length / true_length
  double precision = 0.0;         // share of the reconstruction's length on the truth
  double recall = 0.0;            // share of the truth's length on the reconstruction
  double ours_to_truth = 0.0;     // mean distance of the reconstruction to the truth, world units
  double truth_to_ours = 0.0;     // mean distance of the truth to the reconstruction
  double chamfer = 0.0;           // mean of both, world units
  double chamfer_fraction = 0.0;  // chamfer / height
  // DuplicatedLength of each, world units (0 when not measured). A length
  // ratio met with duplicates is padded: length_ratio_once is the ratio
  // without them.
  double duplicated_length = 0.0, true_duplicated_length = 0.0;
  double length_ratio_once = 0.0;                 // (length - duplicated_length) / true_length
  std::vector<OrderFigures> orders, true_orders;  // index = branch order

  // One line for humans.
  std::string BriefReport() const;
};

// Per order: the number of branch axes and their summed length.
std::vector<OrderFigures> FiguresPerOrder(const SkeletonGraph& skeleton);

// Compares `reconstructed` with `truth`; `height` (> 0) scales the tolerance
// and the sampling (the true tree's height). Both skeletons need an edge.
SkeletonComparison CompareSkeletons(const SkeletonGraph& reconstructed, const SkeletonGraph& truth,
                                    double height, const SkeletonComparisonOptions& options = {});

}  // namespace sylva

#endif  // SYLVA_DATASETS_EVAL_SKELETON_METRICS_H_
