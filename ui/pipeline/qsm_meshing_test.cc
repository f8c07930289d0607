#include "ui/pipeline/qsm_meshing.h"

#include <gtest/gtest.h>

#include <set>

#include "core/util/check.h"
#include "mesh/allometry.h"

namespace sylva {
namespace {

// A trunk of two segments with one branch.
SkeletonGraph SmallTree(const Eigen::Vector3d& base) {
  SkeletonGraph s;
  const int root = s.AddNode(base, 0.2, -1, 0);
  const int n1 = s.AddNode(base + Eigen::Vector3d(0, 0, 1), 0.15, root, 0);
  s.AddNode(base + Eigen::Vector3d(0, 0, 2), 0.1, n1, 0);
  s.AddNode(base + Eigen::Vector3d(1, 0, 1.5), 0.05, n1, 1);
  return s;
}

TEST(QsmMeshingTest, SkeletonPartsBecomeOneTableWithARootEach) {
  const QsmModel qsm = QsmFromSkeletonParts({SmallTree({0, 0, 0}), SmallTree({5, 0, 0})}, "m");
  ASSERT_EQ(qsm.cylinders.size(), 6u);
  std::set<int64_t> ids, branches;
  int roots = 0;
  for (const QsmCylinder& c : qsm.cylinders) {
    ids.insert(c.id);
    branches.insert(c.branch);
    roots += c.parent_id == 0 ? 1 : 0;
  }
  EXPECT_EQ(ids.size(), 6u);
  EXPECT_EQ(branches.size(), 4u);  // trunk and branch of each part
  EXPECT_EQ(roots, 2);
  EXPECT_EQ(SkeletonsFromQsm(qsm).size(), 2u);
}

// An MTG with coordinates only: the pipe model sets the radii, its trunk
// radius 1.5 % of the height unless given.
TEST(QsmMeshingTest, MtgWithoutRadiiGetsPipeModelRadii) {
  const std::string text =
      "CODE:\tFORM-A\nCLASSES:\nSYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
      "$\t0\tFREE\tFREE\tIMPLICIT\nP\t1\tFREE\tFREE\tIMPLICIT\nS\t2\tFREE\tFREE\tEXPLICIT\n"
      "DESCRIPTION:\nLEFT\tRIGHT\tRELTYPE\tMAX\nS\tS\t<\t1\nS\tS\t+\t?\n"
      "FEATURES:\nNAME\tTYPE\nXX\tREAL\nYY\tREAL\nZZ\tREAL\n"
      "MTG:\nENTITY-CODE\t\t\tXX\tYY\tZZ\n/P1\n\t/S1\t\t0\t0\t0\n\t^<S2\t\t0\t0\t2\n"
      "\t^+S3\t\t1\t0\t3\n\t^<S4\t\t0\t0\t4\n";
  const Mtg mtg = ParseMtg(text, "coordinates.mtg");
  MtgMeshingOptions options;
  options.scale = 0.5;
  options.units = "m";
  const MtgTable table = MtgTableForMeshing(mtg, "coordinates.mtg", options);
  ASSERT_EQ(table.parts.size(), 1u);
  EXPECT_EQ(table.pipe_model_parts, 1);
  const SkeletonGraph& tree = table.parts[0];
  ASSERT_EQ(tree.NumNodes(), 4);
  EXPECT_DOUBLE_EQ(tree.Height(), 2.0);  // 4 x 0.5
  EXPECT_DOUBLE_EQ(tree.nodes[0].radius, kDefaultTrunkRadiusFraction * 2.0);
  EXPECT_EQ(tree.radius_source, kAllometricPrior);
  for (const SkeletonNode& node : tree.nodes) EXPECT_GT(node.radius, 0.0);
  EXPECT_EQ(table.qsm.cylinders.size(), 3u);
  EXPECT_EQ(table.qsm.units, "m");
  options.trunk_radius = -1;
  EXPECT_THROW(MtgTableForMeshing(mtg, "coordinates.mtg", options), InputError);
}

}  // namespace
}  // namespace sylva
