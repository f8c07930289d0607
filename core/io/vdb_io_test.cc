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
  old[8] = static_cast<char>(240);  // newer than the linked OpenVDB
  AtomicWriteString(path, old);
  EXPECT_NE(ReadError(path).find("file version 240"), std::string::npos) << ReadError(path);
}

// Voxels in several root children, leaves full and sparse, and values
// stored as half floats (as other tools may write them): the layout check
// walks each as OpenVDB reads it.
TEST(VdbIoTest, TreesOfEveryShapeAreRead) {
  DensityGrid grid(0.5, Eigen::Vector3d(1, 2, 3));
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      for (int k = 0; k < 8; ++k) grid.SetValue({i, j, k}, 0.001f * (i + 8 * j + 64 * k));
    }
  }
  for (const Eigen::Vector3i& far : {Eigen::Vector3i(-5000, 3, 9), Eigen::Vector3i(4100, -9000, 1),
                                     Eigen::Vector3i(70, 80, 90000)}) {
    grid.SetValue(far, 0.5f);
  }
  const fs::path path = TestDir() / "shapes.vdb";
  WriteDensityGrid(path, grid);
  const DensityGrid back = ReadDensityGrid(path);
  EXPECT_EQ(back.NumActiveVoxels(), grid.NumActiveVoxels());
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    EXPECT_FLOAT_EQ(back.Value(ijk), alpha) << ijk.transpose();
  });

  InitializeOpenVdb();
  openvdb::FloatGrid::Ptr half = VdbGrid(grid).deepCopy();
  half->setSaveFloatAsHalf(true);
  const fs::path half_path = TestDir() / "half.vdb";
  openvdb::io::File file(half_path.string());
  file.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);
  file.write(openvdb::GridCPtrVec{half});
  file.close();
  const DensityGrid from_half = ReadDensityGrid(half_path);
  EXPECT_EQ(from_half.NumActiveVoxels(), grid.NumActiveVoxels());
  EXPECT_NEAR(from_half.Value({7, 7, 7}), 0.511f, 1e-3f);
  EXPECT_NEAR(from_half.Value({4100, -9000, 1}), 0.5f, 1e-3f);

  // The delayed-loading metadata holds a byte per leaf, raw or compressed
  // (padded to 128 bytes when 48 to 127 leaves): every count reads.
  for (int leaves : {1, 47, 48, 90, 127, 128, 400}) {
    DensityGrid row(0.125, Eigen::Vector3d::Zero());
    for (int i = 0; i < leaves; ++i) row.SetValue({8 * i, 0, 0}, 0.5f);
    WriteDensityGrid(path, row);
    EXPECT_EQ(ReadDensityGrid(path).NumActiveVoxels(), leaves);
  }
}

// A damaged child mask states thousands of nodes a few kilobytes cannot
// hold: refused before OpenVDB allocates them (it asked for 1.6 GB).
TEST(VdbIoTest, NodesTheFileCannotHoldAreRefused) {
  const fs::path ours = TestDir() / "nodes.vdb";
  WriteDensityGrid(ours, SmallGrid());
  const std::string bytes = ReadFileToString(ours);
  const fs::path path = TestDir() / "damaged_nodes.vdb";
  // After the transform: buffer count, background, tile and child counts,
  // the first child's origin, then its child mask.
  const size_t tree = bytes.find("UniformScaleMap") + 15 + 5 * 24;
  // Every bit of the upper node's child mask set (32768 nodes, 1025 bytes
  // each at the least) and the bytes after its masks zero (no active tile
  // to stop at first): the walk runs out of file. OpenVDB would first make
  // the 32768 nodes (about 1 GB).
  std::string bomb = bytes;
  const size_t child_mask = tree + 28, mask_bytes = 4096;
  std::memset(bomb.data() + child_mask, 0xff, mask_bytes);
  std::memset(bomb.data() + child_mask + mask_bytes, 0, bomb.size() - child_mask - mask_bytes);
  AtomicWriteString(path, bomb);
  EXPECT_NE(ReadError(path).find("runs past its end"), std::string::npos) << ReadError(path);
  // A child whose origin is not on the root's grid of 4096 voxels.
  std::string origin = bytes;
  origin[tree + 16] = 1;
  AtomicWriteString(path, origin);
  EXPECT_NE(ReadError(path).find("a root child's origin"), std::string::npos) << ReadError(path);
  // Another grid type.
  std::string type = bytes;
  type.replace(type.find("Tree_float_5_4_3"), 16, "Tree_int32_5_4_3");
  AtomicWriteString(path, type);
  EXPECT_NE(ReadError(path).find("float grids"), std::string::npos) << ReadError(path);
  // Cut anywhere in the leaves' values.
  AtomicWriteString(path, bytes.substr(0, bytes.size() - 30));
  EXPECT_NE(ReadError(path).find("runs past its end"), std::string::npos) << ReadError(path);
}

// OpenVDB reads a metadata value of fixed size whatever size the file
// states, a bool's byte into a bool, and allocates the leaf count its
// delayed-loading metadata states: each is checked first.
TEST(VdbIoTest, MetadataOpenVdbWouldMisreadIsRefused) {
  const fs::path ours = TestDir() / "metadata.vdb";
  DensityGrid grid(0.125, Eigen::Vector3d::Zero());  // enough leaves for Blosc to pay
  for (int i = 0; i < 400; ++i) grid.SetValue({8 * i, 0, 0}, 0.5f);
  WriteDensityGrid(ours, grid);
  const std::string bytes = ReadFileToString(ours);
  const fs::path path = TestDir() / "damaged_metadata.vdb";
  const auto expect_refused = [&](const std::string& damaged) {
    AtomicWriteString(path, damaged);
    EXPECT_NE(ReadError(path).find("a grid's metadata at byte"), std::string::npos)
        << ReadError(path);
  };
  std::string vec3i = bytes;  // the bounding box's size 12 stated as 4
  ASSERT_EQ(vec3i[bytes.find("vec3i") + 5], 12);
  vec3i[bytes.find("vec3i") + 5] = 4;
  expect_refused(vec3i);
  const size_t delayed = bytes.find("__delayedload") + 13;  // then size, leaf count
  std::string leaves = bytes;
  leaves[delayed + 7] = '\x7f';
  expect_refused(leaves);
  std::string blosc = bytes;  // the mask's Blosc buffer stated 1 byte longer
  ASSERT_GT(blosc[delayed + 8], 0);
  ++blosc[delayed + 8];
  expect_refused(blosc);
  // A bool whose byte is 2 (undefined behaviour in OpenVDB): the string
  // "class" made a bool (the file's size kept).
  std::string boolean = bytes;
  const size_t type = bytes.find("string", bytes.find("class"));
  boolean.replace(type - 4, 4 + 6 + 4, std::string("\x04\0\0\0bool\x01\0\0\0\x02\0", 14));
  expect_refused(boolean);
  std::string unknown = bytes;  // a type OpenVDB does not register
  unknown.replace(bytes.find("vec3i"), 5, "vec9z");
  AtomicWriteString(path, unknown);
  EXPECT_NE(ReadError(path).find("metadata of type 'vec9z'"), std::string::npos) << ReadError(path);
}

}  // namespace
}  // namespace sylva
