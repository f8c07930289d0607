#include "simulate/skeleton_pruning.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "simulate/skeleton_editing.h"

namespace sylva {
namespace {

// Largest matte value in the 3 x 3 pixels around `pixel`; -1 if outside.
float NeighbourhoodMax(const FloatImage& matte, const Eigen::Vector2d& pixel) {
  const int x = static_cast<int>(std::floor(pixel.x()));
  const int y = static_cast<int>(std::floor(pixel.y()));
  if (x < 0 || y < 0 || x >= matte.width() || y >= matte.height()) return -1.0f;
  float best = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = std::clamp(x + dx, 0, matte.width() - 1);
      const int yy = std::clamp(y + dy, 0, matte.height() - 1);
      best = std::max(best, matte.at(xx, yy));
    }
  }
  return best;
}

// Points every `spacing` along the axis' edges (the junction excluded).
std::vector<Eigen::Vector3d> AxisSamples(const SkeletonGraph& skeleton, const BranchAxis& axis,
                                         double spacing) {
  std::vector<Eigen::Vector3d> samples;
  for (size_t k = 1; k < axis.size(); ++k) {
    const Eigen::Vector3d& a = skeleton.nodes[axis[k - 1]].position;
    const Eigen::Vector3d& b = skeleton.nodes[axis[k]].position;
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int s = 1; s <= steps; ++s) samples.push_back(a + (b - a) * (double(s) / steps));
  }
  return samples;
}

// True if more than `max_fraction` of the samples fall on background in some view.
bool LeavesTheMattes(const std::vector<Eigen::Vector3d>& samples, const ImageSet& views,
                     const std::vector<FloatImage>& mattes, const MattePruningOptions& options) {
  for (int v = 0; v < views.NumViews(); ++v) {
    int seen = 0, outside = 0;
    for (const Eigen::Vector3d& point : samples) {
      Eigen::Vector2d pixel;
      if (!views.Project(v, point, &pixel)) continue;
      const float value = NeighbourhoodMax(mattes[v], pixel);
      if (value < 0.0f) continue;
      ++seen;
      outside += value < options.matte_threshold;
    }
    if (seen > 0 && outside > options.max_outside_fraction * seen) return true;
  }
  return false;
}

double Height(const SkeletonGraph& skeleton) {
  double low = 1e300, high = -1e300;
  for (const SkeletonNode& node : skeleton.nodes) {
    low = std::min(low, node.position.z());
    high = std::max(high, node.position.z());
  }
  return high - low;
}

}  // namespace

std::string MattePruningSummary::BriefReport() const {
  std::ostringstream out;
  out << "Pruning: " << removed_axes << " of " << tested_axes
      << " thin branches left the mattes and were removed (" << removed_nodes << " nodes, "
      << removed_strands << " strands)";
  if (painted_axes > 0) out << "; " << painted_axes << " kept: they carry painted density";
  out << ".";
  return out.str();
}

SkeletonGraph PruneBranchesOutsideMattes(const SkeletonGraph& skeleton, const ImageSet& views,
                                         const std::vector<FloatImage>& mattes,
                                         const MattePruningOptions& options,
                                         MattePruningSummary* summary,
                                         const PaintedDensity* painted) {
  options.Check();
  skeleton.Check();
  SYLVA_CHECK(static_cast<int>(mattes.size()) == views.NumViews());
  MattePruningSummary local;
  if (summary == nullptr) summary = &local;
  *summary = MattePruningSummary();
  const int root = skeleton.RootIdx();
  if (root < 0 || options.max_strand_fraction == 0) return skeleton;
  const double max_strands = options.max_strand_fraction * skeleton.nodes[root].strands;
  const double spacing = std::max(options.sample_spacing_fraction * Height(skeleton), 1e-12);

  // Axes are listed parent axes first; an axis hanging off a removed one is
  // skipped (it goes with its parent).
  std::vector<char> removed(skeleton.NumNodes(), 0);
  std::vector<int> strands_taken(skeleton.NumNodes(), 0);  // per junction node
  const std::vector<char> carrying =
      painted != nullptr ? painted->CarryingWood(skeleton) : std::vector<char>(removed.size(), 0);
  for (const BranchAxis& axis : skeleton.BranchAxes()) {
    if (axis.size() < 2 || removed[axis[0]] || removed[axis[1]]) continue;
    if (skeleton.nodes[axis[1]].strands > max_strands) continue;
    if (carrying[axis[1]]) {
      ++summary->painted_axes;
      continue;
    }
    ++summary->tested_axes;
    if (!LeavesTheMattes(AxisSamples(skeleton, axis, spacing), views, mattes, options)) continue;
    ++summary->removed_axes;
    summary->removed_strands += skeleton.nodes[axis[1]].strands;
    strands_taken[axis[0]] += skeleton.nodes[axis[1]].strands;
    for (size_t k = 1; k < axis.size(); ++k) removed[axis[k]] = 1;
  }
  MarkDescendants(skeleton, &removed);
  summary->removed_nodes = static_cast<int>(std::count(removed.begin(), removed.end(), 1));
  SkeletonGraph pruned = skeleton;
  TakeStrands(strands_taken, removed, &pruned);
  return WithoutNodes(pruned, removed);
}

}  // namespace sylva
