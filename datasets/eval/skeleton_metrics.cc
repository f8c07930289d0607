#include "datasets/eval/skeleton_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "core/geometry/point_grid.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// Points along every edge, each standing for the stretch of edge around it
// (its weight, world units): the midpoints of pieces at most `spacing` long.
struct EdgeSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
};

EdgeSamples SampleEdges(const SkeletonGraph& skeleton, double spacing) {
  EdgeSamples samples;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const Eigen::Vector3d& parent = skeleton.nodes[node.parent_idx].position;
    const double length = (node.position - parent).norm();
    if (length == 0.0) continue;
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / spacing)));
    for (int s = 0; s < pieces; ++s) {
      samples.points.push_back(parent + (node.position - parent) * ((s + 0.5) / pieces));
      samples.weights.push_back(length / pieces);
    }
  }
  return samples;
}

// Over `from`: the weighted share within `tolerance` of `to`, and the
// weighted mean distance to it.
void Directed(const EdgeSamples& from, const PointGrid& to, double tolerance, double* share,
              double* mean) {
  double near = 0.0, total = 0.0, sum = 0.0;
  for (size_t i = 0; i < from.points.size(); ++i) {
    double d = 0.0;
    to.Nearest(from.points[i], std::numeric_limits<double>::infinity(), &d);
    total += from.weights[i];
    sum += from.weights[i] * d;
    if (d <= tolerance) near += from.weights[i];
  }
  *share = near / total;
  *mean = sum / total;
}

}  // namespace

std::vector<OrderFigures> FiguresPerOrder(const SkeletonGraph& skeleton) {
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = skeleton.BranchAxes(&orders);
  std::vector<OrderFigures> figures;
  for (size_t a = 0; a < axes.size(); ++a) {
    if (orders[a] >= static_cast<int>(figures.size())) figures.resize(orders[a] + 1);
    OrderFigures& order = figures[orders[a]];
    ++order.axes;
    for (size_t k = 1; k < axes[a].size(); ++k) {
      order.length +=
          (skeleton.nodes[axes[a][k]].position - skeleton.nodes[axes[a][k - 1]].position).norm();
    }
  }
  return figures;
}

SkeletonComparison CompareSkeletons(const SkeletonGraph& reconstructed, const SkeletonGraph& truth,
                                    double height, const SkeletonComparisonOptions& options) {
  SYLVA_CHECK(height > 0) << "the reference height must be positive, got " << height;
  SYLVA_CHECK(options.tolerance_fraction > 0 && options.spacing_fraction > 0);
  const double spacing = options.spacing_fraction * height;
  const EdgeSamples ours = SampleEdges(reconstructed, spacing);
  const EdgeSamples theirs = SampleEdges(truth, spacing);
  SYLVA_CHECK(!ours.points.empty() && !theirs.points.empty())
      << "comparing a skeleton without edges";
  SkeletonComparison result;
  result.height = height;
  result.length = reconstructed.TotalLength();
  result.true_length = truth.TotalLength();
  result.length_ratio = result.length / result.true_length;
  const double tolerance = options.tolerance_fraction * height;
  Directed(ours, PointGrid(theirs.points), tolerance, &result.precision, &result.ours_to_truth);
  Directed(theirs, PointGrid(ours.points), tolerance, &result.recall, &result.truth_to_ours);
  result.chamfer = 0.5 * (result.ours_to_truth + result.truth_to_ours);
  result.chamfer_fraction = result.chamfer / height;
  result.orders = FiguresPerOrder(reconstructed);
  result.true_orders = FiguresPerOrder(truth);
  return result;
}

std::string SkeletonComparison::BriefReport() const {
  std::ostringstream out;
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer),
                "length %.2f x truth (%.1f of %.1f), precision %.3f, recall %.3f, Chamfer %.2f %% "
                "of height (ours->truth %.2f, truth->ours %.2f); axes per order (ours/truth):",
                length_ratio, length, true_length, precision, recall, 100 * chamfer_fraction,
                100 * ours_to_truth / height, 100 * truth_to_ours / height);
  out << buffer;
  const size_t n = std::max(orders.size(), true_orders.size());
  for (size_t k = 0; k < n; ++k) {
    out << " " << (k < orders.size() ? orders[k].axes : 0) << "/"
        << (k < true_orders.size() ? true_orders[k].axes : 0);
  }
  return out.str();
}

}  // namespace sylva
