#include "core/io/vdb_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "core/types/density_grid_vdb.h"
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

DensityGrid SmallGrid() {
  DensityGrid grid(0.125, Eigen::Vector3d::Zero());
  for (int i = 0; i < 40; ++i) grid.SetValue({i, 2 * i, -i}, 0.01f * i);
  return grid;
}

std::string ReadError(const fs::path& path) {
  try {
    ReadDensityGrid(path);
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string());
    return error.what();
  }
  return "read";
}

// sylva writes its grids uncompressed by zlib or Blosc, and refuses files
// compressed so: OpenVDB 10.0's decompressors trust a damaged size.
TEST(VdbIoTest, GridsAreWrittenAndReadWithoutZlibOrBlosc) {
  const fs::path ours = TestDir() / "ours.vdb";
  WriteDensityGrid(ours, SmallGrid());
  const std::string bytes = ReadFileToString(ours);
  uint64_t grid_position = 0;  // the descriptor's first field after 3 strings
  const size_t descriptor = bytes.find("Tree_float_5_4_3") + 16 + 4;  // + instance parent ""
  std::memcpy(&grid_position, bytes.data() + descriptor, 8);
  uint32_t compression = 0;
  std::memcpy(&compression, bytes.data() + grid_position, 4);
  EXPECT_EQ(compression, 0x2u);  // active mask only
  EXPECT_EQ(ReadDensityGrid(ours).NumActiveVoxels(), 39);

  // Blosc as OpenVDB writes it; zlib by the flags alone (Debian's OpenVDB
  // writes no zlib: it drops the flag).
  InitializeOpenVdb();
  const fs::path blosc = TestDir() / "blosc.vdb";
  openvdb::io::File file(blosc.string());
  file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
  file.write(openvdb::GridCPtrVec{VdbGrid(SmallGrid()).copyGrid()});
  file.close();
  EXPECT_NE(ReadError(blosc).find("compressed with Blosc"), std::string::npos) << ReadError(blosc);
  std::string zip = bytes;
  zip[grid_position] = 0x1;
  AtomicWriteString(TestDir() / "zlib.vdb", zip);
  EXPECT_NE(ReadError(TestDir() / "zlib.vdb").find("compressed with zlib"), std::string::npos)
      << ReadError(TestDir() / "zlib.vdb");
}

// A damaged or truncated file is refused before OpenVDB reads it, with the
// byte where it breaks.
TEST(VdbIoTest, DamagedLayoutSaysWhereItBreaks) {
  const fs::path ours = TestDir() / "whole.vdb";
  WriteDensityGrid(ours, SmallGrid());
  const std::string bytes = ReadFileToString(ours);
  const fs::path path = TestDir() / "damaged.vdb";
  // Cut in the UUID, in the grid's type name and in its metadata.
  for (size_t cut : {size_t{30}, bytes.find("Tree_float") + 4, bytes.find("class") + 2}) {
    AtomicWriteString(path, bytes.substr(0, cut));
    EXPECT_NE(ReadError(path).find("runs past its end"), std::string::npos) << ReadError(path);
  }
  // The grid name's length made huge: no 4 GB string is allocated.
  std::string huge = bytes;
  const size_t name_length = bytes.find("density") - 4;
  huge[name_length + 3] = '\x7f';
  AtomicWriteString(path, huge);
  EXPECT_NE(ReadError(path).find("runs past its end"), std::string::npos) << ReadError(path);
  // The grid's end before its start.
  std::string positions = bytes;
  const size_t end_field = bytes.find("Tree_float_5_4_3") + 16 + 4 + 16;
  std::memset(positions.data() + end_field, 0, 8);
  AtomicWriteString(path, positions);
  EXPECT_NE(ReadError(path).find("a grid's positions at byte"), std::string::npos)
      << ReadError(path);
  // The tree's buffer count after the transform (OpenVDB would go on to read
  // the root's tiles from the wrong place).
  std::string buffers = bytes;
  const size_t tree = bytes.find("UniformScaleMap") + 15 + 5 * 24;
  ASSERT_EQ(buffers[tree], 1);
  buffers[tree] = 2;
  AtomicWriteString(path, buffers);
  EXPECT_NE(ReadError(path).find("the tree's buffer count"), std::string::npos) << ReadError(path);
  // Not a .vdb, and an old file version.
  std::string magic = bytes;
  magic[1] = 'X';
  AtomicWriteString(path, magic);
  EXPECT_NE(ReadError(path).find("not a .vdb"), std::string::npos) << ReadError(path);
  std::string old = bytes;
  old[8] = static_cast<char>(200);
  AtomicWriteString(path, old);
  EXPECT_NE(ReadError(path).find("file version 200"), std::string::npos) << ReadError(path);
}

}  // namespace
}  // namespace sylva
