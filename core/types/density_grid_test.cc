#include "core/types/density_grid.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace sylva
