#include "core/io/attractor_io.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_attractor_io_test";
  fs::create_directories(dir);
  return dir;
}

// A fork with a separate second component; node 3 is the main root although
// it is not node 0.
AttractorGraph2D MakeForest() {
  AttractorGraph2D graph;
  graph.width = 1440;
  graph.height = 1080;
  graph.source = "livewire";
  const int tip = graph.AddNode({700.5, 100.25}, -1);
  const int tip2 = graph.AddNode({800.0 / 3.0, 200.1}, -1);
  const int fork = graph.AddNode({720.125, 600.0}, -1);
  graph.root = graph.AddNode({720.5, 1050.5}, -1);
  graph.nodes[tip].parent_idx = fork;
  graph.nodes[tip2].parent_idx = fork;
  graph.nodes[fork].parent_idx = graph.root;
  const int other = graph.AddNode({100, 900}, -1);
  graph.AddNode({90.75, 700}, other);
  return graph;
}

TEST(AttractorIoTest, RoundTripIsExact) {
  const AttractorGraph2D graph = MakeForest();
  const fs::path path = TestDir() / "IMG_0001.json";
  WriteAttractorGraphJson(path, graph, "IMG_0001.jpg");
  const std::string text = ReadFileToString(path);
  EXPECT_NE(text.find("\"format\": \"sylva-attractor-graph\""), std::string::npos) << text;
  EXPECT_NE(text.find("\n    [0, 2],\n"), std::string::npos) << text;  // one edge per line
  std::string image;
  const AttractorGraph2D back = ReadAttractorGraphJson(path, &image);
  EXPECT_EQ(image, "IMG_0001.jpg");
  EXPECT_EQ(back.width, 1440);
  EXPECT_EQ(back.height, 1080);
  EXPECT_EQ(back.source, "livewire");
  EXPECT_EQ(back.root, 3);
  ASSERT_EQ(back.NumNodes(), graph.NumNodes());
  for (int i = 0; i < graph.NumNodes(); ++i) {
    EXPECT_EQ(back.nodes[i].position, graph.nodes[i].position) << i;
    EXPECT_EQ(back.nodes[i].parent_idx, graph.nodes[i].parent_idx) << i;
  }
}

TEST(AttractorIoTest, EmptyGraphRoundTrips) {
  AttractorGraph2D graph;
  graph.width = 10;
  graph.height = 20;
  graph.source = "strokes";
  const fs::path path = TestDir() / "empty.json";
  WriteAttractorGraphJson(path, graph, "a \"quoted\" name.jpg");
  std::string image;
  const AttractorGraph2D back = ReadAttractorGraphJson(path, &image);
  EXPECT_EQ(image, "a \"quoted\" name.jpg");
  EXPECT_TRUE(back.IsEmpty());
  EXPECT_EQ(back.root, -1);
  EXPECT_EQ(back.height, 20);
}

TEST(AttractorIoTest, RefusesToWriteAnInvalidGraph) {
  AttractorGraph2D graph = MakeForest();
  graph.root = 0;  // has a parent
  EXPECT_THROW(WriteAttractorGraphJson(TestDir() / "never.json", graph, "x.jpg"), Error);
  EXPECT_FALSE(fs::exists(TestDir() / "never.json"));
}

TEST(AttractorIoTest, RejectsBrokenFilesNamingFileAndLocation) {
  const fs::path path = TestDir() / "bad.json";
  const auto expect_error = [&](const std::string& text, const std::string& where) {
    AtomicWriteString(path, text);
    try {
      ReadAttractorGraphJson(path);
      ADD_FAILURE() << "expected InputError for " << text;
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string()) << text;
      EXPECT_NE(error.message().find(where), std::string::npos) << error.message();
    }
  };
  const std::string head =
      R"({"format": "sylva-attractor-graph", "version": 1, "image": "a.jpg", "width": 100, )"
      R"("height": 50, "source": "edited", )";
  const std::string nodes = R"("nodes": [[1, 2], [3, 4], [5, 6]], )";
  // Sanity: the base document itself reads.
  AtomicWriteString(path, head + nodes + R"("edges": [[1, 0], [2, 1]], "root": 0})");
  EXPECT_EQ(ReadAttractorGraphJson(path).NumEdges(), 2);

  expect_error(R"({"format": "sylva-attractor-graph", "version": 1,)", "invalid JSON");
  expect_error("[1, 2]", "expected an object");
  expect_error(R"({"format": "sylva-skeleton", "version": 1})", "at /format");
  expect_error(R"({"format": "sylva-attractor-graph", "version": 2})", "unsupported version 2");
  expect_error(R"({"format": "sylva-attractor-graph", "version": 1, "width": 1})",
               "missing key 'image'");
  expect_error(head + R"("nodes": [[1, 2], [3, "x"]], "edges": [], "root": 0})",
               "at /nodes/1/1: expected a number");
  expect_error(head + R"("nodes": [[1, 2], [3]], "edges": [], "root": 0})",
               "at /nodes/1: expected 2 numbers");
  expect_error(head + R"("nodes": [[1, 2e999]], "edges": [], "root": 0})", "number overflow");
  expect_error(head + nodes + R"("edges": [[1, 3]], "root": 0})",
               "at /edges/0: node index 3 out of range");
  expect_error(head + nodes + R"("edges": [[1, 0], [1, 2]], "root": 0})",
               "at /edges/1: node 1 has a second parent");
  expect_error(head + nodes + R"("edges": [[1, 1]], "root": 0})", "its own parent");
  expect_error(head + nodes + R"("edges": [[1, 2], [2, 1]], "root": 0})", "at /edges: ");
  expect_error(head + nodes + R"("edges": [[1, 2], [2, 1]], "root": 0})", "cycle");
  expect_error(head + nodes + R"("edges": [[1, 0]], "root": 1})", "at /root: must be the index");
  expect_error(head + nodes + R"("edges": [[1, 0]], "root": 7})", "at /root");
  expect_error(head + R"("nodes": [], "edges": [], "root": 0})", "at /root: must be -1");
  expect_error(head + nodes + R"("edges": [[1, 0.5]], "root": 0})",
               "at /edges/0/1: expected an integer");
  expect_error(R"({"format": "sylva-attractor-graph", "version": 1, "image": "a.jpg", )"
               R"("width": 0, "height": 50})",
               "at /width: must be a positive number");
}

TEST(AttractorIoTest, MissingFileNamesTheFile) {
  const fs::path path = TestDir() / "does_not_exist.json";
  try {
    ReadAttractorGraphJson(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("does_not_exist.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace sylva
