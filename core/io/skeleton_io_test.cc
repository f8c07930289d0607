#include "core/io/skeleton_io.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_skeleton_io_test";
  fs::create_directories(dir);
  return dir;
}

TEST(SkeletonIoTest, RoundTripIsExact) {
  SkeletonGraph skeleton;
  skeleton.radius_source = "ground truth";
  const int root = skeleton.AddNode({0, 0, 0}, 0.16, -1, 0);
  const int top = skeleton.AddNode({0.01, -0.02, 1.0 / 3.0}, 0.1234567890123, root, 0);
  skeleton.AddNode({1e-9, 2.5, 3.75}, 0.0, top, 1);
  const fs::path path = TestDir() / "skeleton.json";
  WriteSkeletonJson(path, skeleton, "m");
  std::string units;
  const SkeletonGraph back = ReadSkeletonJson(path, &units);
  EXPECT_EQ(units, "m");
  EXPECT_EQ(back.radius_source, "ground truth");
  ASSERT_EQ(back.NumNodes(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(back.nodes[i].position, skeleton.nodes[i].position);
    EXPECT_EQ(back.nodes[i].radius, skeleton.nodes[i].radius);
    EXPECT_EQ(back.nodes[i].parent_idx, skeleton.nodes[i].parent_idx);
    EXPECT_EQ(back.nodes[i].order, skeleton.nodes[i].order);
  }
}

TEST(SkeletonIoTest, PlyRoundTripInAdTreeLayout) {
  SkeletonGraph skeleton;
  skeleton.radius_source = "allometric prior";
  const int root = skeleton.AddNode({0, 0, 0}, 0.16, -1, 0);
  const int top = skeleton.AddNode({0.5, -0.25, 2}, 0.1, root, 0);
  skeleton.AddNode({1, 2.5, 3.75}, 0.05, top, 1);
  skeleton.AddNode({-1, 0, 3}, 0.07, top, 1);
  const int strands[] = {10, 10, 4, 6};
  for (int i = 0; i < 4; ++i) skeleton.nodes[i].strands = strands[i];
  const fs::path path = TestDir() / "skeleton.ply";
  WriteSkeletonPly(path, skeleton, "m");
  const std::string text = ReadFileToString(path);
  EXPECT_NE(text.find("element vertex 4\nproperty float x"), std::string::npos) << text;
  EXPECT_NE(text.find("property float radius"), std::string::npos);
  EXPECT_NE(text.find("element edge 3\nproperty list uchar int vertex_indices"), std::string::npos);
  EXPECT_NE(text.find("radius: allometric prior"), std::string::npos);
  const SkeletonGraph back = ReadSkeletonPly(path);
  EXPECT_EQ(back.radius_source, "allometric prior");
  ASSERT_EQ(back.NumNodes(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(back.nodes[i].position.isApprox(skeleton.nodes[i].position, 1e-7));
    EXPECT_NEAR(back.nodes[i].radius, skeleton.nodes[i].radius, 1e-8);
    EXPECT_EQ(back.nodes[i].parent_idx, skeleton.nodes[i].parent_idx);
    EXPECT_EQ(back.nodes[i].strands, skeleton.nodes[i].strands);
    EXPECT_EQ(back.nodes[i].order, skeleton.nodes[i].order);
  }
  AtomicWriteString(TestDir() / "cut.ply", text.substr(0, text.size() - 10));
  EXPECT_THROW(ReadSkeletonPly(TestDir() / "cut.ply"), InputError);
}

TEST(SkeletonIoTest, RejectsBrokenFiles) {
  const fs::path path = TestDir() / "bad.json";
  const std::string head = R"({"format": "sylva-skeleton", "version": 1, "nodes": [)";
  const auto expect_error = [&](const std::string& nodes, const std::string& where) {
    AtomicWriteString(path, head + nodes + "]}");
    try {
      ReadSkeletonJson(path);
      ADD_FAILURE() << "expected InputError for " << nodes;
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string());
      EXPECT_NE(error.message().find(where), std::string::npos) << error.message();
    }
  };
  expect_error(R"({"position": [0, 0], "radius": 1, "parent": -1, "order": 0})",
               "/nodes/0/position");
  expect_error(R"({"position": [0, 0, 0], "radius": -1, "parent": -1, "order": 0})",
               "/nodes/0/radius");
  expect_error(R"({"position": [0, 0, 0], "radius": 1, "parent": 3, "order": 0})",
               "/nodes/0/parent");
  expect_error(R"({"position": [0, 0, 0], "radius": 1, "parent": -1, "order": 0},
                  {"position": [0, 0, 1], "radius": 1, "parent": -1, "order": 0})",
               "2 roots");
}

}  // namespace
}  // namespace sylva
