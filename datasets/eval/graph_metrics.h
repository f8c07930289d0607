// Ground truth and distances for 2D attractor graphs: a skeleton projected
// into a view, and Chamfer-style distances between graphs in pixels.
#ifndef SYLVA_DATASETS_EVAL_GRAPH_METRICS_H_
#define SYLVA_DATASETS_EVAL_GRAPH_METRICS_H_

#include <Eigen/Core>
#include <vector>

#include "core/types/attractor_graph.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "datasets/eval/point_metrics.h"

namespace sylva {

// The skeleton's nodes of branch order <= max_order (and the edges between
// them, parent links kept) projected into view `view_idx` (ImageSet::Project:
// pinhole, distorted or orthographic), as an attractor graph of that view's
// image size; root = the projected skeleton root, source "ground truth".
// A node whose parent is of higher order (not possible for orders assigned by
// SkeletonGraph::AssignOrders) becomes a root. Throws InputError if a kept
// node lies behind a pinhole camera.
AttractorGraph2D ProjectSkeleton(const SkeletonGraph& skeleton, const ImageSet& image_set,
                                 int view_idx, int max_order);

// Distances between two graphs sampled every `spacing_px` pixels along their
// edges (AttractorGraph2D::SamplePoints); a = first graph. Distances are in
// pixels; both graphs must have nodes.
PointSetDistances CompareGraphs2D(const AttractorGraph2D& a, const AttractorGraph2D& b,
                                  double spacing_px);
// The same against a plain list of image points (b).
PointSetDistances CompareGraphs2D(const AttractorGraph2D& a, const std::vector<Eigen::Vector2d>& b,
                                  double spacing_px);

}  // namespace sylva

#endif  // SYLVA_DATASETS_EVAL_GRAPH_METRICS_H_
