#include "core/io/mtg_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "core/io/plant_export_test_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

using testing_util::BundledSkeletons;
using testing_util::kSourceDir;
using testing_util::kTestData;
using testing_util::MaxNodeError;
using testing_util::TinyTree;

const fs::path kOpenAleaDir = kSourceDir / "datasets" / "openalea-mtg";

std::string ParseError(const std::string& text) {
  try {
    const Mtg mtg = ParseMtg(text, "bad.mtg");
    SkeletonsFromMtg(mtg, "bad.mtg");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// A valid file (one axis of two segments) to break in the tests.
std::string SmallFile() { return ReadFileToString(kTestData / "tiny_tree.mtg"); }

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// The golden file was checked by hand against OpenAlea's syntax page
// (doc/user/syntax.rst) and reader (io.py): TABs as column separators,
// features from the TAB cell of "XX" in the ENTITY-CODE line, '^' continuing
// the column's code above, a branch's '+A' line in its parent axis' column
// and its first S one column further (OpenAlea links that S with '+' to the
// junction's S).
TEST(MtgIoTest, TinyTreeMatchesTheGoldenFile) {
  const std::string golden = ReadFileToString(kTestData / "tiny_tree.mtg");
  const std::string written = MtgText({TinyTree()}, "m");
  std::istringstream e(golden), a(written);
  std::string le, la;
  int line = 0;
  while (std::getline(e, le)) {
    ++line;
    ASSERT_TRUE(static_cast<bool>(std::getline(a, la))) << "missing line " << line;
    EXPECT_EQ(le, la) << "line " << line;
  }
  EXPECT_FALSE(static_cast<bool>(std::getline(a, la))) << "extra lines";
}

TEST(MtgIoTest, GoldenFileReadsAsOpenAleaWould) {
  const Mtg mtg = ReadMtg(kTestData / "tiny_tree.mtg");
  // $, P1, A1..A4, 8 S.
  ASSERT_EQ(mtg.entities.size(), 14u);
  EXPECT_EQ(mtg.feature_names, (std::vector<std::string>{"XX", "YY", "ZZ", "radius"}));
  int branch_starts = 0;
  for (const MtgEntity& e : mtg.entities) {
    if (e.symbol != "S") continue;
    EXPECT_EQ(e.scale, 3);
    EXPECT_EQ(mtg.entities[e.complex_idx].symbol, "A") << e.label << " line " << e.line;
    EXPECT_EQ(e.features.size(), 4u);
    if (e.edge == '+') {
      ++branch_starts;
      EXPECT_EQ(e.label, "S1");
      EXPECT_EQ(mtg.entities[e.parent_idx].symbol, "S");
    }
  }
  EXPECT_EQ(branch_starts, 3);
  std::vector<std::vector<int>> order;
  MtgText({TinyTree()}, "m", &order);
  const MtgSkeletons read = SkeletonsFromMtg(mtg, "tiny_tree.mtg");
  ASSERT_EQ(read.parts.size(), 1u);
  EXPECT_EQ(read.radius_feature, "radius");
  EXPECT_EQ(MaxNodeError(TinyTree(), read.parts[0], order[0]), 0.0);
  for (int k = 0; k < read.parts[0].NumNodes(); ++k) {
    EXPECT_EQ(read.parts[0].nodes[k].order, TinyTree().nodes[order[0][k]].order);
  }
}

TEST(MtgIoTest, BundledSkeletonsRoundTripWithin1em6) {
  for (const auto& [name, skeleton] : BundledSkeletons()) {
    std::vector<std::vector<int>> order;
    const std::string text = MtgText({skeleton}, "m", &order);
    const MtgSkeletons read = SkeletonsFromMtg(ParseMtg(text, name), name);
    ASSERT_EQ(read.parts.size(), 1u) << name;
    // Zero-length edges are merged on reading; the bundled skeletons have none.
    EXPECT_EQ(read.merged_nodes, 0) << name;
    const double error = MaxNodeError(skeleton, read.parts[0], order[0]);
    std::printf("%s (%d nodes): largest position/radius error %.3g\n", name.c_str(),
                skeleton.NumNodes(), error);
    EXPECT_LT(error, 1e-6) << name;
  }
}

TEST(MtgIoTest, SeveralSkeletonsBecomeSeveralPlants) {
  SkeletonGraph second = TinyTree();
  for (SkeletonNode& node : second.nodes) node.position += Eigen::Vector3d(5, 0, 0);
  std::vector<std::vector<int>> order;
  const std::string text = MtgText({TinyTree(), second}, "m", &order);
  const MtgSkeletons read = SkeletonsFromMtg(ParseMtg(text, "two"), "two");
  ASSERT_EQ(read.parts.size(), 2u);
  EXPECT_EQ(MaxNodeError(second, read.parts[1], order[1]), 0.0);
}

// OpenAlea's own test trees (datasets/openalea-mtg).
TEST(MtgIoTest, ReadsTheReconstructedAppleTree) {
  const fs::path path = kOpenAleaDir / "reconstructed_appletree.mtg";
  const MtgSkeletons read = SkeletonsFromMtg(ReadMtg(path), path.string());
  ASSERT_EQ(read.parts.size(), 1u);
  EXPECT_EQ(read.geometry_scale, 3);
  EXPECT_EQ(read.radius_feature, "");  // only XX YY ZZ: the caller sets radii
  EXPECT_EQ(read.unplaced_entities, 0);
  EXPECT_GT(read.placed_entities, 300);
  const SkeletonGraph& tree = read.parts[0];
  EXPECT_EQ(tree.NumNodes(), read.placed_entities - read.merged_nodes);
  // The first two S of B1 from the file.
  EXPECT_LT((tree.nodes[0].position - Eigen::Vector3d(0.109826, 0.0258136, -0.359779)).norm(),
            1e-12);
  EXPECT_EQ(tree.nodes[1].parent_idx, 0);
  EXPECT_GT(tree.Tips().size(), 50u);
}

TEST(MtgIoTest, ReadsTheDigitisedWalnutBranch) {
  const fs::path path = kOpenAleaDir / "boutdenoylum2.mtg";
  MtgToSkeletonOptions options;
  options.diameter_unit = 10;  // walnut.drf: DiameterUnit = 10 (mm diameters, cm coordinates)
  const MtgSkeletons read = SkeletonsFromMtg(ReadMtg(path), path.string(), options);
  ASSERT_EQ(read.parts.size(), 1u);
  EXPECT_EQ(read.geometry_scale, 3);
  EXPECT_EQ(read.radius_feature, "TopDia");
  // The trunk axis A1 gives the base point below its first S.
  EXPECT_EQ(read.base_nodes, 1);
  const SkeletonGraph& tree = read.parts[0];
  EXPECT_LT((tree.nodes[0].position - Eigen::Vector3d(-3.45, -21.07, -27.23)).norm(), 1e-12);
  EXPECT_LT((tree.nodes[1].position - Eigen::Vector3d(-2.5, -17.68, 121.43)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(tree.nodes[1].radius, 180.0 / 2 / 10);  // S1: TopDia 180 mm = 9 cm radius
  for (const SkeletonNode& node : tree.nodes) EXPECT_GT(node.radius, 0.0);
}

TEST(MtgIoTest, ReadsTheAgrafAppleTree) {
  const fs::path path = kOpenAleaDir / "agraf.mtg";
  const Mtg mtg = ReadMtg(path);
  const MtgSkeletons read = SkeletonsFromMtg(mtg, path.string());
  EXPECT_EQ(read.geometry_scale, 3);
  EXPECT_EQ(read.radius_feature, "TopDia");
  // E1<<E35 and the like code entities without coordinates.
  EXPECT_GT(read.unplaced_entities, 0);
  ASSERT_GE(read.parts.size(), 1u);
  for (const SkeletonGraph& part : read.parts) part.Check();
}

TEST(MtgIoTest, BadFilesGiveANamedError) {
  const std::string good = SmallFile();
  EXPECT_EQ(ParseError(good), "no error");
  EXPECT_NE(ParseError(Replace(good, "CODE:\tFORM-A", "CODE:\tFORM-B")).find("FORM-B"),
            std::string::npos);
  EXPECT_NE(ParseError(Replace(good, "CODE:\tFORM-A", "HELLO")).find("bad.mtg:3"),
            std::string::npos)
      << ParseError(Replace(good, "CODE:\tFORM-A", "HELLO"));
  EXPECT_NE(ParseError(Replace(good, "S\t3\tNONE", "S\tthree\tNONE")).find("bad scale"),
            std::string::npos);
  EXPECT_NE(ParseError(Replace(good, "^<S2", "^<Q2")).find("class 'Q'"), std::string::npos);
  EXPECT_NE(ParseError(Replace(good, "\t0\t0\t1\t0.15", "\t0\t0\tone\t0.15")).find("'one'"),
            std::string::npos);
  EXPECT_NE(ParseError(Replace(good, "XX\tYY\tZZ\tradius\n/P1", "XX\tYY\tZZ\tdiam\n/P1"))
                .find("'diam' is not declared"),
            std::string::npos);
  const std::string no_xyz = Replace(Replace(good, "XX\tREAL", "X\tREAL"),
                                     "XX\tYY\tZZ\tradius\n/P1", "X\tYY\tZZ\tradius\n/P1");
  EXPECT_NE(ParseError(no_xyz).find("no entity has all of the features XX, YY and ZZ"),
            std::string::npos);
  EXPECT_NE(ParseError(Replace(good, "\t\t^<S2", "\t\t\t\t\t^<S2")).find("indented further"),
            std::string::npos);
}

}  // namespace
}  // namespace sylva
