#include "datasets/eval/skeleton_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <unordered_map>

#include "core/geometry/point_grid.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// Two stretches within the duplicate radius of each other are one branch
// traced twice when they lie more than this many radii apart along the
// skeleton (closer, they are the same branch or a fork's first stretch).
constexpr double kDuplicateApart = 3.0;

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

double DuplicatedLength(const SkeletonGraph& skeleton, double radius, double spacing) {
  SYLVA_CHECK(radius > 0 && spacing > 0) << "radius and spacing must be positive";
  const SkeletonPathLengths paths(skeleton);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  std::vector<int> edges;         // each sample's edge (its child node)
  std::vector<double> from_root;  // and its distance from the root along the skeleton
  for (int k = 0; k < skeleton.NumNodes(); ++k) {
    const int parent = skeleton.nodes[k].parent_idx;
    if (parent < 0) continue;
    const Eigen::Vector3d& from = skeleton.nodes[parent].position;
    const Eigen::Vector3d& to = skeleton.nodes[k].position;
    const double length = (to - from).norm();
    if (length == 0.0) continue;
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / spacing)));
    for (int s = 0; s < pieces; ++s) {
      const double t = (s + 0.5) / pieces;
      points.push_back(from + (to - from) * t);
      weights.push_back(length / pieces);
      edges.push_back(k);
      from_root.push_back(paths.FromRoot(k, points.back()));
    }
  }
  // Samples hashed into cells of the radius: a pair lies in neighbouring cells.
  auto cell_of = [&](const Eigen::Vector3d& p) -> Eigen::Vector3i {
    return (p / radius).array().floor().cast<int>();
  };
  auto key_of = [](const Eigen::Vector3i& c) -> int64_t {
    return ((static_cast<int64_t>(c.x()) & 0x1fffff) << 42) |
           ((static_cast<int64_t>(c.y()) & 0x1fffff) << 21) |
           (static_cast<int64_t>(c.z()) & 0x1fffff);
  };
  std::unordered_map<int64_t, std::vector<int>> cells;
  for (size_t i = 0; i < points.size(); ++i) cells[key_of(cell_of(points[i]))].push_back(i);
  std::vector<char> duplicate(points.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3i c = cell_of(points[i]);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto found = cells.find(key_of(c + Eigen::Vector3i(dx, dy, dz)));
          if (found == cells.end()) continue;
          for (const int j : found->second) {
            if (j <= static_cast<int>(i) || edges[i] == edges[j]) continue;
            if ((points[i] - points[j]).squaredNorm() > radius * radius) continue;
            if (paths.Between(edges[i], from_root[i], edges[j], from_root[j]) <=
                kDuplicateApart * radius) {
              continue;
            }
            // The thinner stretch is the second trace (ties: the later node).
            const SkeletonNode& a = skeleton.nodes[edges[i]];
            const SkeletonNode& b = skeleton.nodes[edges[j]];
            const bool i_is_second =
                a.strands != b.strands ? a.strands < b.strands : edges[i] > edges[j];
            duplicate[i_is_second ? i : j] = 1;
          }
        }
  }
  double length = 0.0;
  for (size_t i = 0; i < points.size(); ++i) length += duplicate[i] ? weights[i] : 0.0;
  return length;
}

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
  result.length_ratio_once = result.length_ratio;
  if (options.duplicate_fraction > 0) {
    const double radius = options.duplicate_fraction * height;
    const double spacing = std::min(options.spacing_fraction * height, 0.25 * radius);
    result.duplicated_length = DuplicatedLength(reconstructed, radius, spacing);
    result.true_duplicated_length = DuplicatedLength(truth, radius, spacing);
    result.length_ratio_once = (result.length - result.duplicated_length) / result.true_length;
  }
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
  if (duplicated_length > 0 || true_duplicated_length > 0) {
    std::snprintf(buffer, sizeof(buffer),
                  "; traced twice %.0f %% of our length (truth %.0f %%): %.2f x truth once",
                  100 * duplicated_length / length, 100 * true_duplicated_length / true_length,
                  length_ratio_once);
    out << buffer;
  }
  return out.str();
}

}  // namespace sylva
