#include "mesh/crown_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/util/check.h"

namespace sylva {

void CrownVolumeOptions::Check() const {
  SYLVA_CHECK_INPUT(scale >= 0 && std::isfinite(scale), "CrownVolume.scale") << "must be >= 0";
  SYLVA_CHECK_INPUT(support_fraction > 0 && support_fraction <= 1, "CrownVolume.support_fraction")
      << "must be in (0, 1]";
}

namespace {

// Opacities are capped here before taking -log(1 - alpha) (an opaque voxel
// would have infinite extinction and weight).
constexpr double kMaxOpacity = 1.0 - 1e-6;

// The voxels of the active voxels' bounding box grown by a margin, x
// fastest. The margin keeps the outermost layer empty.
class DenseBox {
 public:
  DenseBox(const DensityGrid& density, int margin) {
    Eigen::Vector3i hi;
    density.ActiveIndexBounds(&lo_, &hi);
    lo_ -= Eigen::Vector3i::Constant(margin);
    dims_ = hi + Eigen::Vector3i::Constant(margin) - lo_ + Eigen::Vector3i::Ones();
    strides_ = {1, static_cast<size_t>(dims_.x()), static_cast<size_t>(dims_.x()) * dims_.y()};
  }

  size_t Size() const { return strides_[2] * dims_.z(); }
  int Dim(int axis) const { return dims_[axis]; }
  size_t Stride(int axis) const { return strides_[axis]; }
  size_t Index(const Eigen::Vector3i& ijk) const {
    const Eigen::Vector3i d = ijk - lo_;
    return d.x() + d.y() * strides_[1] + d.z() * strides_[2];
  }
  // The coordinate along `axis` of the voxel at `index`, in box voxels.
  int Coordinate(size_t index, int axis) const {
    return static_cast<int>(index / strides_[axis] % dims_[axis]);
  }
  // The world z of the centres of box layer `layer`.
  double WorldZ(const DensityGrid& density, int layer) const {
    return density.WorldFromIndex(Eigen::Vector3d(0, 0, lo_.z() + layer)).z();
  }
  // The box layer of the first voxels whose centres lie at or above `z`.
  int FirstLayerAbove(const DensityGrid& density, double z) const {
    const double k = std::ceil(density.IndexFromWorld(Eigen::Vector3d(0, 0, z)).z() - 1e-9);
    return static_cast<int>(std::clamp(k - lo_.z(), 0.0, static_cast<double>(dims_.z())));
  }

 private:
  Eigen::Vector3i lo_, dims_;
  std::array<size_t, 3> strides_;
};

// The value v at which the values >= v hold half of the sum of `values`
// (all >= 0): the median weighted by the values themselves.
double SelfWeightedMedian(std::vector<float> values) {
  std::sort(values.begin(), values.end());
  double total = 0.0;
  for (float v : values) total += v;
  double below = 0.0;
  for (float v : values) {
    below += v;
    if (below >= 0.5 * total) return v;
  }
  return values.empty() ? 0.0 : values.back();
}

// Per box voxel, the extinction of the crown's voxels (0 elsewhere).
std::vector<float> CrownExtinction(const DensityGrid& density, const DenseBox& box,
                                   int first_layer) {
  std::vector<float> sigma(box.Size(), 0.0f);
  const double voxel_size = density.voxel_size();
  density.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    const size_t index = box.Index(ijk);
    if (box.Coordinate(index, 2) < first_layer) return;
    sigma[index] =
        static_cast<float>(-std::log1p(-std::min<double>(alpha, kMaxOpacity)) / voxel_size);
  });
  return sigma;
}

// Dilates `mask` by a cube of half side `w` voxels (one axis at a time).
void Dilate(const DenseBox& box, int w, std::vector<char>* mask) {
  std::vector<char> out(mask->size(), 0);
  std::vector<int> prefix;
  for (int axis = 0; axis < 3; ++axis) {
    const int n = box.Dim(axis);
    const size_t stride = box.Stride(axis);
    for (size_t start = 0; start < mask->size(); ++start) {
      if (box.Coordinate(start, axis) != 0) continue;  // each line once, from its first voxel
      prefix.assign(n + 1, 0);
      for (int i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + (*mask)[start + i * stride];
      for (int i = 0; i < n; ++i) {
        out[start + i * stride] = prefix[std::min(n, i + w + 1)] > prefix[std::max(0, i - w)];
      }
    }
    mask->swap(out);
  }
}

// Closes `mask` (dilation, then erosion) by a cube of half side `w` voxels.
void Close(const DenseBox& box, int w, std::vector<char>* mask) {
  if (w <= 0) return;
  Dilate(box, w, mask);
  for (char& m : *mask) m = !m;
  Dilate(box, w, mask);
  for (char& m : *mask) m = !m;
}

// Adds to `mask` every voxel the outside (flood fill from the box's empty
// corner, 6-connected) does not reach.
void FillCavities(const DenseBox& box, std::vector<char>* mask) {
  std::vector<char> outside(mask->size(), 0);
  std::vector<size_t> stack = {0};
  outside[0] = 1;
  while (!stack.empty()) {
    const size_t index = stack.back();
    stack.pop_back();
    for (int axis = 0; axis < 3; ++axis) {
      const int at = box.Coordinate(index, axis);
      for (int step : {-1, 1}) {
        if (at + step < 0 || at + step >= box.Dim(axis)) continue;
        const size_t next = step < 0 ? index - box.Stride(axis) : index + box.Stride(axis);
        if ((*mask)[next] || outside[next]) continue;
        outside[next] = 1;
        stack.push_back(next);
      }
    }
  }
  for (size_t i = 0; i < mask->size(); ++i) (*mask)[i] = !outside[i];
}

// The share of envelope voxel `index` to count: 1 inside; on the surface,
// its extinction over the median of its 26 neighbours' in the envelope.
double Share(const DenseBox& box, const std::vector<char>& envelope,
             const std::vector<float>& sigma, size_t index, std::vector<float>* neighbours) {
  bool surface = false;
  neighbours->clear();
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        // The envelope never touches the box's outer layer: neighbours exist.
        const size_t n = index + dx + dy * box.Stride(1) + dz * box.Stride(2);
        if (n == index) continue;
        if (std::abs(dx) + std::abs(dy) + std::abs(dz) == 1 && !envelope[n]) surface = true;
        if (envelope[n] && sigma[n] > 0) neighbours->push_back(sigma[n]);
      }
    }
  }
  if (!surface) return 1.0;
  if (neighbours->empty()) return sigma[index] > 0 ? 1.0 : 0.0;
  auto middle = neighbours->begin() + neighbours->size() / 2;
  std::nth_element(neighbours->begin(), middle, neighbours->end());
  return std::min(1.0, static_cast<double>(sigma[index]) / *middle);
}

}  // namespace

DensityCrown MeasureDensityCrown(const DensityGrid& density, double crown_base_z,
                                 const CrownVolumeOptions& options) {
  options.Check();
  DensityCrown crown;
  if (density.IsEmpty()) return crown;
  const double voxel_size = density.voxel_size();
  const int w = static_cast<int>(std::lround(options.scale / voxel_size));
  const DenseBox box(density, w + 2);
  const std::vector<float> sigma =
      CrownExtinction(density, box, box.FirstLayerAbove(density, crown_base_z));
  std::vector<float> active;
  for (float s : sigma) {
    if (s > 0) active.push_back(s);
  }
  if (active.empty()) return crown;
  const double support = options.support_fraction * SelfWeightedMedian(std::move(active));
  std::vector<char> envelope(sigma.size());
  for (size_t i = 0; i < sigma.size(); ++i) envelope[i] = sigma[i] > 0 && sigma[i] >= support;
  Close(box, w, &envelope);
  FillCavities(box, &envelope);
  double voxels = 0.0;
  int top_layer = -1;
  std::vector<float> neighbours;
  for (size_t i = 0; i < envelope.size(); ++i) {
    if (!envelope[i]) continue;
    voxels += Share(box, envelope, sigma, i, &neighbours);
    top_layer = std::max(top_layer, box.Coordinate(i, 2));
  }
  crown.volume = voxels * std::pow(voxel_size, 3);
  if (top_layer >= 0) crown.top_z = box.WorldZ(density, top_layer);
  return crown;
}

double DensityCrownVolume(const DensityGrid& density, double crown_base_z,
                          const CrownVolumeOptions& options) {
  return MeasureDensityCrown(density, crown_base_z, options).volume;
}

}  // namespace sylva
