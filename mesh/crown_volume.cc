#include "mesh/crown_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
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

// The voxels of a bounding box (index space) grown by a margin, x fastest.
// The margin keeps the outermost layer empty.
class DenseBox {
 public:
  DenseBox(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, int margin) {
    lo_ = lo - Eigen::Vector3i::Constant(margin);
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
  bool Contains(const Eigen::Vector3i& ijk) const {
    const Eigen::Vector3i d = ijk - lo_;
    return (d.array() >= 0).all() && (d.array() < dims_.array()).all();
  }
  // The world z of the centres of box layer `layer`.
  double WorldZ(const DensityGrid& density, int layer) const {
    return density.WorldFromIndex(Eigen::Vector3d(0, 0, lo_.z() + layer)).z();
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

// The crown's voxels: active, centre at or above `crown_base_z`, with their
// extinction (> 0).
struct CrownVoxel {
  Eigen::Vector3i ijk;
  float sigma;
};
std::vector<CrownVoxel> CrownVoxels(const DensityGrid& density, double crown_base_z) {
  const double first_k =
      std::ceil(density.IndexFromWorld(Eigen::Vector3d(0, 0, crown_base_z)).z() - 1e-9);
  const double voxel_size = density.voxel_size();
  std::vector<CrownVoxel> voxels;
  density.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    if (ijk.z() < first_k) return;
    const auto sigma =
        static_cast<float>(-std::log1p(-std::min<double>(alpha, kMaxOpacity)) / voxel_size);
    if (sigma > 0) voxels.push_back({ijk, sigma});
  });
  return voxels;
}

// Dilates `mask` by a cube of half side `w` voxels (one axis at a time).
// Along an axis, the lines of one block of the box (its voxels with the same
// coordinates on the slower axes) are swept together, layer by layer, with a
// count per line of the mask's voxels in the window [k - w, k + w]: every
// layer is contiguous in memory.
void Dilate(const DenseBox& box, int w, std::vector<char>* mask) {
  std::vector<char> out(mask->size(), 0);
  std::vector<int> count;
  for (int axis = 0; axis < 3; ++axis) {
    const int n = box.Dim(axis);
    const size_t layer = box.Stride(axis);  // voxels per layer of a block
    const size_t block = layer * n;
    if (layer == 1) {  // along x: each line alone, with one count
      for (size_t start = 0; start < mask->size(); start += block) {
        const char* in = mask->data() + start;
        char* result = out.data() + start;
        int window = 0;
        for (int k = 0; k < std::min(w, n); ++k) window += in[k];
        for (int k = 0; k < n; ++k) {
          if (k + w < n) window += in[k + w];
          if (k - w - 1 >= 0) window -= in[k - w - 1];
          result[k] = window > 0;
        }
      }
      mask->swap(out);
      continue;
    }
    count.assign(layer, 0);
    for (size_t start = 0; start < mask->size(); start += block) {
      const char* in = mask->data() + start;
      char* result = out.data() + start;
      std::fill(count.begin(), count.end(), 0);
      for (int k = 0; k < std::min(w, n); ++k) {
        for (size_t i = 0; i < layer; ++i) count[i] += in[k * layer + i];
      }
      for (int k = 0; k < n; ++k) {
        if (k + w < n) {
          for (size_t i = 0; i < layer; ++i) count[i] += in[(k + w) * layer + i];
        }
        if (k - w - 1 >= 0) {
          for (size_t i = 0; i < layer; ++i) count[i] -= in[(k - w - 1) * layer + i];
        }
        for (size_t i = 0; i < layer; ++i) result[k * layer + i] = count[i] > 0;
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
  // Scanline flood fill: runs along x, seeds in the four neighbouring rows.
  const int nx = box.Dim(0), ny = box.Dim(1), nz = box.Dim(2);
  std::vector<char> outside(mask->size(), 0);
  const auto open = [&](size_t index) { return !(*mask)[index] && !outside[index]; };
  std::vector<Eigen::Vector3i> seeds = {Eigen::Vector3i::Zero()};
  while (!seeds.empty()) {
    const Eigen::Vector3i seed = seeds.back();
    seeds.pop_back();
    const size_t row = seed.y() * box.Stride(1) + seed.z() * box.Stride(2);
    if (!open(row + seed.x())) continue;
    int x0 = seed.x(), x1 = seed.x();
    while (x0 > 0 && open(row + x0 - 1)) --x0;
    while (x1 + 1 < nx && open(row + x1 + 1)) ++x1;
    for (int x = x0; x <= x1; ++x) outside[row + x] = 1;
    const std::pair<int, int> neighbours[4] = {{seed.y() - 1, seed.z()},
                                               {seed.y() + 1, seed.z()},
                                               {seed.y(), seed.z() - 1},
                                               {seed.y(), seed.z() + 1}};
    for (const auto& [y, z] : neighbours) {
      if (y < 0 || y >= ny || z < 0 || z >= nz) continue;
      const size_t next = y * box.Stride(1) + z * box.Stride(2);
      // One seed per run of open voxels beside [x0, x1].
      for (int x = x0; x <= x1; ++x) {
        if (open(next + x) && (x == x0 || !open(next + x - 1))) seeds.emplace_back(x, y, z);
      }
    }
  }
  for (size_t i = 0; i < mask->size(); ++i) (*mask)[i] = !outside[i];
}

// The share of envelope voxel `index` to count: 1 inside; on the surface,
// its extinction over the median of its 26 neighbours' in the envelope.
double Share(const DenseBox& box, const std::vector<char>& envelope,
             const std::vector<float>& sigma, size_t index, std::vector<float>* neighbours) {
  // The envelope never touches the box's outer layer: neighbours exist.
  bool surface = false;
  for (int axis = 0; axis < 3 && !surface; ++axis) {
    surface = !envelope[index - box.Stride(axis)] || !envelope[index + box.Stride(axis)];
  }
  if (!surface) return 1.0;
  neighbours->clear();
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const size_t n = index + dx + dy * box.Stride(1) + dz * box.Stride(2);
        if (n != index && envelope[n] && sigma[n] > 0) neighbours->push_back(sigma[n]);
      }
    }
  }
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
  const std::vector<CrownVoxel> voxels = CrownVoxels(density, crown_base_z);
  if (voxels.empty()) return crown;
  std::vector<float> sigmas;
  for (const CrownVoxel& voxel : voxels) sigmas.push_back(voxel.sigma);
  const double support = options.support_fraction * SelfWeightedMedian(std::move(sigmas));
  // The envelope lies within w voxels of the supported voxels (closing), its
  // surface's neighbours one more: a box around them with a margin of w + 2
  // holds everything the measure reads, and is often much smaller than the
  // grid's.
  Eigen::Vector3i lo = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i hi = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  for (const CrownVoxel& voxel : voxels) {
    if (voxel.sigma < support) continue;
    lo = lo.cwiseMin(voxel.ijk);
    hi = hi.cwiseMax(voxel.ijk);
  }
  const DenseBox box(lo, hi, w + 2);
  std::vector<float> sigma(box.Size(), 0.0f);
  for (const CrownVoxel& voxel : voxels) {
    if (box.Contains(voxel.ijk)) sigma[box.Index(voxel.ijk)] = voxel.sigma;
  }
  std::vector<char> envelope(sigma.size());
  for (size_t i = 0; i < sigma.size(); ++i) envelope[i] = sigma[i] > 0 && sigma[i] >= support;
  Close(box, w, &envelope);
  FillCavities(box, &envelope);
  double envelope_voxels = 0.0;
  int top_layer = -1;
  std::vector<float> neighbours;
  for (size_t i = 0; i < envelope.size(); ++i) {
    if (!envelope[i]) continue;
    envelope_voxels += Share(box, envelope, sigma, i, &neighbours);
    top_layer = std::max(top_layer, static_cast<int>(i / box.Stride(2)));
  }
  crown.volume = envelope_voxels * std::pow(voxel_size, 3);
  if (top_layer >= 0) crown.top_z = box.WorldZ(density, top_layer);
  return crown;
}

double DensityCrownVolume(const DensityGrid& density, double crown_base_z,
                          const CrownVolumeOptions& options) {
  return MeasureDensityCrown(density, crown_base_z, options).volume;
}

}  // namespace sylva
