#include "core/types/density_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/types/density_grid_vdb.h"

namespace sylva {
namespace {

TEST(DensityGridTest, TransformAndValues) {
  DensityGrid grid(0.5, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(grid.WorldFromIndex(Eigen::Vector3d(2, 0, -2)).isApprox(Eigen::Vector3d(2, 2, 2)));
  EXPECT_TRUE(grid.IndexFromWorld(Eigen::Vector3d(2, 2, 2)).isApprox(Eigen::Vector3d(2, 0, -2)));
  EXPECT_TRUE(grid.IsEmpty());
  grid.SetValue({1, 2, 3}, 0.5f);
  grid.SetValue({-4, 0, 0}, 2.0f);  // clamped
  grid.SetValue({5, 5, 5}, 0.0f);   // stays inactive
  EXPECT_EQ(grid.NumActiveVoxels(), 2);
  EXPECT_FLOAT_EQ(grid.Value({1, 2, 3}), 0.5f);
  EXPECT_FLOAT_EQ(grid.Value({-4, 0, 0}), 1.0f);
  EXPECT_FLOAT_EQ(grid.Value({0, 0, 0}), 0.0f);
  Eigen::Vector3i lo, hi;
  ASSERT_TRUE(grid.ActiveIndexBounds(&lo, &hi));
  EXPECT_EQ(lo, Eigen::Vector3i(-4, 0, 0));
  EXPECT_EQ(hi, Eigen::Vector3i(1, 2, 3));
  const Box3d box = grid.ActiveWorldBounds();
  EXPECT_TRUE(box.min().isApprox(Eigen::Vector3d(1 - 2.25, 2 - 0.25, 3 - 0.25)));
  EXPECT_NEAR(grid.SumOfValues(), 1.5, 1e-6);
  grid.SetValue({1, 2, 3}, -1.0f);
  EXPECT_EQ(grid.NumActiveVoxels(), 1);
}

TEST(DensityGridTest, CopyIsDeep) {
  DensityGrid a(1.0, Eigen::Vector3d::Zero());
  a.SetValue({0, 0, 0}, 0.3f);
  a.SetMetadata("units", "m");
  DensityGrid b = a;
  b.SetValue({0, 0, 0}, 0.9f);
  EXPECT_FLOAT_EQ(a.Value({0, 0, 0}), 0.3f);
  EXPECT_FLOAT_EQ(b.Value({0, 0, 0}), 0.9f);
  EXPECT_EQ(b.GetMetadata("units"), "m");
  EXPECT_EQ(b.GetMetadata("missing"), "");
}

// The active voxels and opacities in the order of OpenVDB's tree iterator
// over active values (a tile expanded voxel by voxel, x slowest as its
// bounding box iterates).
void ReferenceOrder(const DensityGrid& grid, std::vector<Eigen::Vector3i>* voxels,
                    std::vector<float>* values) {
  for (auto it = VdbGrid(grid).cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (auto c = box.begin(); c; ++c) {
      voxels->emplace_back((*c).x(), (*c).y(), (*c).z());
      values->push_back(*it);
    }
  }
}

// Checks ForEachActive, ActiveValues and ActiveVoxelsAt against that order.
void ExpectReferenceOrder(const DensityGrid& grid) {
  std::vector<Eigen::Vector3i> reference_voxels;
  std::vector<float> reference_values;
  ReferenceOrder(grid, &reference_voxels, &reference_values);
  ASSERT_EQ(static_cast<int64_t>(reference_voxels.size()), grid.NumActiveVoxels());
  std::vector<Eigen::Vector3i> visited;
  std::vector<float> visited_values;
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    visited.push_back(ijk);
    visited_values.push_back(alpha);
  });
  EXPECT_EQ(visited, reference_voxels);
  EXPECT_EQ(visited_values, reference_values);
  EXPECT_EQ(grid.ActiveValues(), reference_values);
  // Every place, then a sparse ascending pick with repeats.
  std::vector<int64_t> every(reference_voxels.size());
  for (size_t i = 0; i < every.size(); ++i) every[i] = static_cast<int64_t>(i);
  EXPECT_EQ(grid.ActiveVoxelsAt(every), reference_voxels);
  std::mt19937 random(7);
  std::vector<int64_t> some;
  for (int k = 0; k < 300; ++k) {
    some.push_back(std::uniform_int_distribution<int64_t>(0, every.size() - 1)(random));
  }
  some.push_back(some.front());
  some.push_back(static_cast<int64_t>(every.size()) - 1);
  std::sort(some.begin(), some.end());
  const std::vector<Eigen::Vector3i> picked = grid.ActiveVoxelsAt(some);
  ASSERT_EQ(picked.size(), some.size());
  for (size_t k = 0; k < some.size(); ++k) EXPECT_EQ(picked[k], reference_voxels[some[k]]) << k;
  EXPECT_TRUE(grid.ActiveVoxelsAt({}).empty());
}

TEST(DensityGridTest, ActiveVoxelsInTheTreesOrder) {
  // Scattered voxels on both sides of the origin (several leaves and upper
  // nodes), a dense patch, and some active voxels of opacity 0.
  DensityGrid grid(1.0, Eigen::Vector3d::Zero());
  std::mt19937 random(3);
  std::uniform_int_distribution<int> coordinate(-300, 300);
  std::uniform_real_distribution<float> opacity(0.01f, 1.0f);
  for (int k = 0; k < 3000; ++k) {
    grid.SetValue({coordinate(random), coordinate(random), coordinate(random)}, opacity(random));
  }
  for (int x = 0; x < 20; ++x) {
    for (int y = -10; y < 10; ++y) grid.SetValue({x, y, 5}, 0.5f);
  }
  for (int k = 0; k < 5; ++k) VdbGrid(grid).tree().setValueOn(openvdb::Coord(k, 40, -k), 0.0f);
  ASSERT_FALSE(VdbGrid(grid).tree().hasActiveTiles());
  ExpectReferenceOrder(grid);
  // With an active tile (an 8^3 block at level 1), in the tree's order too.
  VdbGrid(grid).tree().addTile(1, openvdb::Coord(64, 64, 64), 0.25f, true);
  ASSERT_TRUE(VdbGrid(grid).tree().hasActiveTiles());
  ExpectReferenceOrder(grid);
}

}  // namespace
}  // namespace sylva
