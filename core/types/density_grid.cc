#include "core/types/density_grid.h"

#include <algorithm>
#include <mutex>

#include "core/types/density_grid_vdb.h"
#include "core/util/check.h"

namespace sylva {

struct DensityGrid::Impl {
  openvdb::FloatGrid::Ptr grid;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double voxel_size = 1.0;
};

void InitializeOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

namespace {

openvdb::math::Transform::Ptr MakeTransform(double voxel_size, const Eigen::Vector3d& origin) {
  auto transform = openvdb::math::Transform::createLinearTransform(voxel_size);
  transform->postTranslate(openvdb::Vec3d(origin.x(), origin.y(), origin.z()));
  return transform;
}

openvdb::FloatGrid::Ptr MakeEmptyGrid(double voxel_size, const Eigen::Vector3d& origin) {
  InitializeOpenVdb();
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setTransform(MakeTransform(voxel_size, origin));
  grid->setName("density");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  return grid;
}

}  // namespace

DensityGrid::DensityGrid() : DensityGrid(1.0, Eigen::Vector3d::Zero()) {}

DensityGrid::DensityGrid(double voxel_size, const Eigen::Vector3d& origin)
    : impl_(std::make_unique<Impl>()) {
  SYLVA_CHECK(voxel_size > 0 && std::isfinite(voxel_size)) << "voxel size " << voxel_size;
  impl_->grid = MakeEmptyGrid(voxel_size, origin);
  impl_->origin = origin;
  impl_->voxel_size = voxel_size;
}

DensityGrid::~DensityGrid() = default;

DensityGrid::DensityGrid(const DensityGrid& other) : impl_(std::make_unique<Impl>(*other.impl_)) {
  impl_->grid = other.impl_->grid->deepCopy();
}

DensityGrid& DensityGrid::operator=(const DensityGrid& other) {
  if (this != &other) *this = DensityGrid(other);
  return *this;
}

DensityGrid::DensityGrid(DensityGrid&& other) noexcept = default;
DensityGrid& DensityGrid::operator=(DensityGrid&& other) noexcept = default;

double DensityGrid::voxel_size() const { return impl_->voxel_size; }
const Eigen::Vector3d& DensityGrid::origin() const { return impl_->origin; }

float DensityGrid::Value(const Eigen::Vector3i& ijk) const {
  return impl_->grid->tree().getValue(openvdb::Coord(ijk.x(), ijk.y(), ijk.z()));
}

void DensityGrid::SetValue(const Eigen::Vector3i& ijk, float alpha) {
  const openvdb::Coord coord(ijk.x(), ijk.y(), ijk.z());
  if (!(alpha > 0.0f)) {
    impl_->grid->tree().setValueOff(coord, 0.0f);
    return;
  }
  impl_->grid->tree().setValueOn(coord, std::min(alpha, 1.0f));
}

int64_t DensityGrid::NumActiveVoxels() const {
  return static_cast<int64_t>(impl_->grid->activeVoxelCount());
}

bool DensityGrid::ActiveIndexBounds(Eigen::Vector3i* min_ijk, Eigen::Vector3i* max_ijk) const {
  if (IsEmpty()) return false;
  const openvdb::CoordBBox bbox = impl_->grid->evalActiveVoxelBoundingBox();
  *min_ijk = Eigen::Vector3i(bbox.min().x(), bbox.min().y(), bbox.min().z());
  *max_ijk = Eigen::Vector3i(bbox.max().x(), bbox.max().y(), bbox.max().z());
  return true;
}

Box3d DensityGrid::ActiveWorldBounds() const {
  Eigen::Vector3i lo, hi;
  if (!ActiveIndexBounds(&lo, &hi)) return Box3d();
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5);
  return Box3d(WorldFromIndex(lo.cast<double>() - half), WorldFromIndex(hi.cast<double>() + half));
}

namespace {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
constexpr openvdb::Index kLeafWords = FloatLeaf::NodeMaskType::WORD_COUNT;

// Calls visit(offset) for the active voxels of a leaf, in offset order (the
// order of its value-on iterator), word by word of its mask.
template <typename Visit>
void ForEachOnOffset(const FloatLeaf& leaf, const Visit& visit) {
  const FloatLeaf::NodeMaskType& mask = leaf.getValueMask();
  for (openvdb::Index w = 0; w < kLeafWords; ++w) {
    for (uint64_t word = mask.getWord<uint64_t>(w); word != 0; word &= word - 1) {
      visit(static_cast<openvdb::Index>(64 * w + __builtin_ctzll(word)));
    }
  }
}

// The offset of the n-th active voxel of a leaf (n < its count).
openvdb::Index NthOnOffset(const FloatLeaf& leaf, int64_t n) {
  const FloatLeaf::NodeMaskType& mask = leaf.getValueMask();
  for (openvdb::Index w = 0; w < kLeafWords; ++w) {
    uint64_t word = mask.getWord<uint64_t>(w);
    const int on = __builtin_popcountll(word);
    if (n >= on) {
      n -= on;
      continue;
    }
    for (; n > 0; --n) word &= word - 1;
    return static_cast<openvdb::Index>(64 * w + __builtin_ctzll(word));
  }
  SYLVA_CHECK(false) << "a leaf has fewer active voxels than asked";
  return 0;
}

}  // namespace

void DensityGrid::ForEachActive(
    const std::function<void(const Eigen::Vector3i&, float)>& visit) const {
  const openvdb::FloatTree& tree = impl_->grid->tree();
  if (!tree.hasActiveTiles()) {
    // Leaf by leaf, the order of the tree's value iterator below when there
    // are no tiles (depth first, each node's children by position), at a
    // fraction of its cost per voxel.
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
      const float* data = leaf->buffer().data();
      ForEachOnOffset(*leaf, [&](openvdb::Index offset) {
        const openvdb::Coord c = leaf->offsetToGlobalCoord(offset);
        visit(Eigen::Vector3i(c.x(), c.y(), c.z()), data[offset]);
      });
    }
    return;
  }
  for (auto it = impl_->grid->cbeginValueOn(); it; ++it) {
    if (it.isVoxelValue()) {
      const openvdb::Coord c = it.getCoord();
      visit(Eigen::Vector3i(c.x(), c.y(), c.z()), *it);
    } else {
      // Tile: every voxel of its box shares the value.
      openvdb::CoordBBox box;
      it.getBoundingBox(box);
      for (auto c = box.begin(); c; ++c) visit(Eigen::Vector3i((*c).x(), (*c).y(), (*c).z()), *it);
    }
  }
}

std::vector<float> DensityGrid::ActiveValues() const {
  std::vector<float> values;
  values.reserve(NumActiveVoxels());
  const openvdb::FloatTree& tree = impl_->grid->tree();
  if (tree.hasActiveTiles()) {
    ForEachActive([&](const Eigen::Vector3i&, float alpha) { values.push_back(alpha); });
    return values;
  }
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    const float* data = leaf->buffer().data();
    ForEachOnOffset(*leaf, [&](openvdb::Index offset) { values.push_back(data[offset]); });
  }
  return values;
}

std::vector<Eigen::Vector3i> DensityGrid::ActiveVoxelsAt(const std::vector<int64_t>& places) const {
  SYLVA_CHECK(std::is_sorted(places.begin(), places.end()));
  SYLVA_CHECK(places.empty() || (places.front() >= 0 && places.back() < NumActiveVoxels()))
      << "a place beyond the active voxels";
  std::vector<Eigen::Vector3i> voxels;
  voxels.reserve(places.size());
  size_t next = 0;
  const openvdb::FloatTree& tree = impl_->grid->tree();
  if (tree.hasActiveTiles()) {
    int64_t place = 0;
    ForEachActive([&](const Eigen::Vector3i& ijk, float) {
      for (; next < places.size() && places[next] == place; ++next) voxels.push_back(ijk);
      ++place;
    });
    return voxels;
  }
  // Leaf by leaf, by their voxel counts; in a leaf, by its mask's words.
  int64_t first = 0;  // the place of the leaf's first active voxel
  for (auto leaf = tree.cbeginLeaf(); leaf && next < places.size(); ++leaf) {
    const int64_t count = static_cast<int64_t>(leaf->onVoxelCount());
    for (; next < places.size() && places[next] < first + count; ++next) {
      const openvdb::Coord c = leaf->offsetToGlobalCoord(NthOnOffset(*leaf, places[next] - first));
      voxels.emplace_back(c.x(), c.y(), c.z());
    }
    first += count;
  }
  return voxels;
}

double DensityGrid::SumOfValues() const {
  double sum = 0.0;
  ForEachActive([&](const Eigen::Vector3i&, float alpha) { sum += alpha; });
  return sum;
}

void DensityGrid::SetMetadata(const std::string& key, const std::string& value) {
  impl_->grid->insertMeta(key, openvdb::StringMetadata(value));
}

std::string DensityGrid::GetMetadata(const std::string& key) const {
  const auto meta = impl_->grid->getMetadata<openvdb::StringMetadata>(key);
  return meta ? meta->value() : std::string();
}

void DensityGrid::Check() const {
  SYLVA_CHECK(impl_->grid->transform().isLinear());
  ForEachActive([](const Eigen::Vector3i& ijk, float alpha) {
    SYLVA_CHECK(alpha >= 0.0f && alpha <= 1.0f)
        << "voxel (" << ijk.transpose() << ") has opacity " << alpha;
  });
}

openvdb::FloatGrid& VdbGrid(DensityGrid& grid) { return *grid.impl().grid; }
const openvdb::FloatGrid& VdbGrid(const DensityGrid& grid) { return *grid.impl().grid; }

DensityGrid DensityGridFromVdb(const openvdb::FloatGrid& vdb_grid, const std::string& source) {
  const openvdb::math::Transform& transform = vdb_grid.transform();
  const openvdb::Vec3d voxel = transform.voxelSize();
  SYLVA_CHECK_INPUT(transform.isLinear() && transform.hasUniformScale(), source)
      << "grid '" << vdb_grid.getName() << "' must have a uniform linear transform";
  SYLVA_CHECK_INPUT(voxel[0] > 0, source) << "grid voxel size must be positive";
  const openvdb::Vec3d origin = transform.indexToWorld(openvdb::Vec3d(0, 0, 0));
  for (int axis = 0; axis < 3; ++axis) {
    openvdb::Vec3d unit(0, 0, 0);
    unit[axis] = 1;
    const openvdb::Vec3d step = transform.indexToWorld(unit) - origin;
    openvdb::Vec3d expected(0, 0, 0);
    expected[axis] = voxel[0];
    SYLVA_CHECK_INPUT((step - expected).length() <= 1e-9 * voxel[0], source)
        << "grid '" << vdb_grid.getName() << "' is rotated; only axis-aligned grids are supported";
  }
  DensityGrid grid(voxel[0], Eigen::Vector3d(origin.x(), origin.y(), origin.z()));
  grid.impl().grid = vdb_grid.deepCopy();
  grid.impl().grid->setTransform(MakeTransform(voxel[0], grid.origin()));
  return grid;
}

float DensityGrid::MaxValueAround(const Eigen::Vector3d& point_in_world) const {
  const Eigen::Vector3i centre = IndexFromWorld(point_in_world).array().round().cast<int>();
  float best = 0.0f;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        best = std::max(best, Value(centre + Eigen::Vector3i(dx, dy, dz)));
      }
    }
  }
  return best;
}

}  // namespace sylva
