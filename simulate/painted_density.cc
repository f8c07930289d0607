#include "simulate/painted_density.h"

#include <algorithm>
#include <cmath>

#include "core/util/check.h"

namespace sylva {

PaintedDensity::PaintedDensity(const DensityGrid& density, const ImageSet& views,
                               const std::vector<FloatImage>& added, float min_added)
    : density_(density), views_(views), added_(added), min_added_(min_added) {
  SYLVA_CHECK(static_cast<int>(added.size()) == views.NumViews());
  for (const FloatImage& image : added) {
    any_ = any_ || std::any_of(image.values().begin(), image.values().end(),
                               [&](float value) { return value >= min_added; });
  }
}

bool PaintedDensity::Contains(const Eigen::Vector3d& point) const {
  if (!any_ || density_.MaxValueAround(point) <= 0.0f) return false;
  for (int v = 0; v < views_.NumViews(); ++v) {
    const FloatImage& added = added_[v];
    Eigen::Vector2d pixel;
    if (added.values().empty() || !views_.Project(v, point, &pixel)) continue;
    const int x = static_cast<int>(std::floor(pixel.x()));
    const int y = static_cast<int>(std::floor(pixel.y()));
    if (x < 0 || y < 0 || x >= added.width() || y >= added.height()) continue;
    if (added.at(x, y) >= min_added_) return true;
  }
  return false;
}

std::vector<char> PaintedDensity::CarryingWood(const SkeletonGraph& skeleton) const {
  std::vector<char> carrying(skeleton.NumNodes(), 0);
  if (!any_) return carrying;
  // Parents come before children: walk back so each child has passed its
  // mark to its parent before the parent passes it on.
  for (int i = skeleton.NumNodes() - 1; i >= 0; --i) {
    const SkeletonNode& node = skeleton.nodes[i];
    if (!carrying[i] && Contains(node.position)) carrying[i] = 1;
    if (carrying[i] && node.parent_idx >= 0) carrying[node.parent_idx] = 1;
  }
  return carrying;
}

}  // namespace sylva
