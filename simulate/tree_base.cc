#include <algorithm>
#include <map>

#include "core/util/check.h"
#include "simulate/particle_flow.h"

namespace sylva {
namespace {

// One horizontal layer of qualifying voxels.
struct Layer {
  double opacity = 0.0;                                   // summed
  Eigen::Vector2d weighted_xy = Eigen::Vector2d::Zero();  // sum of opacity * (i, j)
};

// The lowest layer whose opacity reaches the fraction of the reference.
int BaseLayer(const std::map<int, Layer>& layers, const TreeBaseOptions& options) {
  const int lowest = layers.begin()->first;
  double reference = 0.0;
  for (auto it = layers.begin();
       it != layers.end() && it->first < lowest + options.reference_voxels; ++it) {
    reference = std::max(reference, it->second.opacity);
  }
  for (const auto& [k, layer] : layers) {
    if (layer.opacity >= options.layer_fraction * reference) return k;
  }
  return lowest;  // not reached: the reference layer itself qualifies
}

}  // namespace

Eigen::Vector3d EstimateTreeBase(const DensityGrid& density, const TreeBaseOptions& options) {
  options.Check();
  std::map<int, Layer> layers;
  density.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    if (!(alpha > 0) || alpha < options.min_opacity) return;
    Layer& layer = layers[ijk.z()];
    layer.opacity += alpha;
    layer.weighted_xy += alpha * ijk.head<2>().cast<double>();
  });
  SYLVA_CHECK_INPUT(!layers.empty(), "density")
      << "no voxel has opacity >= " << options.min_opacity << ": cannot find the tree base";
  const int base_layer = BaseLayer(layers, options);
  Layer slab;
  for (auto it = layers.find(base_layer);
       it != layers.end() && it->first < base_layer + options.slab_voxels; ++it) {
    slab.opacity += it->second.opacity;
    slab.weighted_xy += it->second.weighted_xy;
  }
  const Eigen::Vector2d center = slab.weighted_xy / slab.opacity;
  return density.WorldFromIndex(Eigen::Vector3d(center.x(), center.y(), base_layer - 0.5));
}

}  // namespace sylva
