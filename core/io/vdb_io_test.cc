#include "core/io/vdb_io.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_vdb_io_test";
  fs::create_directories(dir);
  return dir;
}

TEST(VdbIoTest, RoundTripKeepsTransformValuesAndMetadata) {
  DensityGrid grid(0.125, Eigen::Vector3d(-1, 0.5, 2));
  grid.SetValue({0, 0, 0}, 0.25f);
  grid.SetValue({10, -3, 7}, 0.75f);
  grid.SetMetadata("units", "arbitrary");
  const fs::path path = TestDir() / "density.vdb";
  WriteDensityGrid(path, grid);
  const DensityGrid back = ReadDensityGrid(path);
  EXPECT_DOUBLE_EQ(back.voxel_size(), 0.125);
  EXPECT_TRUE(back.origin().isApprox(grid.origin()));
  EXPECT_EQ(back.NumActiveVoxels(), 2);
  EXPECT_FLOAT_EQ(back.Value({10, -3, 7}), 0.75f);
  EXPECT_EQ(back.GetMetadata("units"), "arbitrary");
}

TEST(VdbIoTest, CorruptFileIsInputError) {
  const fs::path path = TestDir() / "corrupt.vdb";
  AtomicWriteString(path, "not a vdb file at all");
  EXPECT_THROW(ReadDensityGrid(path), InputError);
  EXPECT_THROW(ReadDensityGrid(TestDir() / "missing.vdb"), InputError);
}

}  // namespace
}  // namespace sylva
