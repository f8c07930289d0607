#include "core/io/lpy_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "core/io/plant_export_test_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

using testing_util::BundledSkeletons;
using testing_util::kTestData;
using testing_util::MaxNodeError;
using testing_util::TinyTree;

// Line-by-line comparison, so a failure names the first differing line.
void ExpectSameLines(const std::string& expected, const std::string& actual) {
  std::istringstream e(expected), a(actual);
  std::string le, la;
  int line = 0;
  while (true) {
    const bool more_e = static_cast<bool>(std::getline(e, le));
    const bool more_a = static_cast<bool>(std::getline(a, la));
    ++line;
    ASSERT_EQ(more_e, more_a) << "line count differs at line " << line;
    if (!more_e) break;
    EXPECT_EQ(le, la) << "line " << line;
  }
}

std::string InterpretError(const std::string& axiom) {
  try {
    InterpretLpy("# test\nAxiom: " + axiom + "\nderivation length: 0\n", "bad.lpy");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

// The golden files were checked by hand against L-Py's turtle documentation
// (doc/user/turtleBasic.rst: @M, LineTo's 4th argument the top width, _ the
// width; + about U towards L, / about H) and PlantGL's Turtle (H = +Z, L =
// -Y, U = +X at the start). E.g. the branch from (0,0,1) to (1,0,1.5): d =
// (1,0,0.5) has d.H = 0.5, d.L = 0, d.U = 1, so /(90) rolls L onto +X and
// +(atan2(1, 0.5) = 63.43...) turns H onto d.
TEST(LpyIoTest, TinyTreeMatchesTheGoldenFiles) {
  const SkeletonGraph tree = TinyTree();
  ExpectSameLines(ReadFileToString(kTestData / "tiny_tree.lpy"),
                  LpyText({tree}, LpyForm::kAbsolute, "m"));
  ExpectSameLines(ReadFileToString(kTestData / "tiny_tree_turtle.lpy"),
                  LpyText({tree}, LpyForm::kTurtle, "m"));
}

TEST(LpyIoTest, GoldenFilesInterpretToTheTinyTree) {
  const SkeletonGraph tree = TinyTree();
  for (const LpyForm form : {LpyForm::kAbsolute, LpyForm::kTurtle}) {
    std::vector<std::vector<int>> order;
    LpyText({tree}, form, "m", &order);
    const LpyTree read = ReadLpy(
        kTestData / (form == LpyForm::kAbsolute ? "tiny_tree.lpy" : "tiny_tree_turtle.lpy"));
    ASSERT_EQ(read.parts.size(), 1u);
    EXPECT_LT(MaxNodeError(tree, read.parts[0], order[0]), 1e-12);
    for (int k = 0; k < read.parts[0].NumNodes(); ++k) {
      EXPECT_EQ(read.parts[0].nodes[k].order, tree.nodes[order[0][k]].order) << "node " << k;
    }
  }
}

TEST(LpyIoTest, BundledSkeletonsRoundTripWithin1em6) {
  for (const auto& [name, skeleton] : BundledSkeletons()) {
    for (const LpyForm form : {LpyForm::kAbsolute, LpyForm::kTurtle}) {
      std::vector<std::vector<int>> order;
      const std::string text = LpyText({skeleton}, form, "m", &order);
      const LpyTree read = InterpretLpy(text, name);
      ASSERT_EQ(read.parts.size(), 1u) << name;
      const double error = MaxNodeError(skeleton, read.parts[0], order[0]);
      const char* kind = form == LpyForm::kAbsolute ? "absolute" : "turtle";
      std::printf("%s (%d nodes), %s: largest position/radius error %.3g\n", name.c_str(),
                  skeleton.NumNodes(), kind, error);
      EXPECT_LT(error, 1e-6) << name << " " << kind;
    }
  }
}

TEST(LpyIoTest, SeveralSkeletonsStaySeparate) {
  SkeletonGraph second = TinyTree();
  for (SkeletonNode& node : second.nodes) node.position += Eigen::Vector3d(5, 0, 0);
  for (const LpyForm form : {LpyForm::kAbsolute, LpyForm::kTurtle}) {
    std::vector<std::vector<int>> order;
    const LpyTree read = InterpretLpy(LpyText({TinyTree(), second}, form, "m", &order), "two");
    ASSERT_EQ(read.parts.size(), 2u);
    EXPECT_LT(MaxNodeError(second, read.parts[1], order[1]), 1e-12);
  }
}

// The base project's skeleton forks at its root: the branch written there
// (before the trunk's first segment) and the trunk are one tree.
TEST(LpyIoTest, BranchesAtTheRootStayAttached) {
  SkeletonGraph fork;
  const int root = fork.AddNode({0, 0, 0}, 0.1, -1, 0);
  fork.AddNode({0, 0, 1}, 0.08, root, 0);
  fork.AddNode({1, 0, 1}, 0.05, root, 1);
  for (const LpyForm form : {LpyForm::kAbsolute, LpyForm::kTurtle}) {
    std::vector<std::vector<int>> order;
    const std::string text = LpyText({fork}, form, "m", &order);
    const LpyTree read = InterpretLpy(text, "fork");
    ASSERT_EQ(read.parts.size(), 1u) << text;
    EXPECT_LT(MaxNodeError(fork, read.parts[0], order[0]), 1e-12) << text;
  }
}

TEST(LpyIoTest, TurtleSymbolsFollowPlantGL) {
  // F up +Z; +(90) turns H towards L = -Y; &(90) pitches H towards -U.
  const LpyTree tree =
      InterpretLpy("Axiom: _(0.5) F(2) +(90) F(1) &(90) F(1) /(90) -(90) F(1)", "t");
  ASSERT_EQ(tree.parts.size(), 1u);
  const std::vector<SkeletonNode>& n = tree.parts[0].nodes;
  ASSERT_EQ(n.size(), 5u);
  EXPECT_DOUBLE_EQ(n[0].radius, 0.5);
  EXPECT_LT((n[1].position - Eigen::Vector3d(0, 0, 2)).norm(), 1e-12);
  EXPECT_LT((n[2].position - Eigen::Vector3d(0, -1, 2)).norm(), 1e-12);
  // After +(90): H = -Y, L = -Z, U = +X; &(90) about L takes H to -U = -X.
  EXPECT_LT((n[3].position - Eigen::Vector3d(-1, -1, 2)).norm(), 1e-12);
  // After &(90): H = -X, L = -Z, U = -Y. /(90) about H: L -> U = -Y, U -> -L = +Z.
  // -(90) about U = +Z turns H away from L: H -> -L = +Y.
  EXPECT_LT((n[4].position - Eigen::Vector3d(-1, 0, 2)).norm(), 1e-12);
}

TEST(LpyIoTest, BadAxiomsNameTheFileLineAndColumn) {
  EXPECT_NE(InterpretError("F(1) Q(2)").find("bad.lpy:2:13"), std::string::npos)
      << InterpretError("F(1) Q(2)");
  EXPECT_NE(InterpretError("F(1) Q(2)").find("module 'Q'"), std::string::npos);
  EXPECT_NE(InterpretError("[F(1)").find("not closed"), std::string::npos);
  EXPECT_NE(InterpretError("F(1)]").find("without '['"), std::string::npos);
  EXPECT_NE(InterpretError("F(1,x)").find("'x' is not a number"), std::string::npos);
  EXPECT_NE(InterpretError("LineTo(1,2)").find("LineTo takes 3-4 arguments"), std::string::npos);
  EXPECT_NE(InterpretError("F(1").find("'(' not closed"), std::string::npos);
  EXPECT_THROW(InterpretLpy("derivation length: 0\n", "none.lpy"), InputError);
}

}  // namespace
}  // namespace sylva
