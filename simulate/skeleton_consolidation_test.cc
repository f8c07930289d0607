#include "simulate/skeleton_consolidation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kVoxel = 0.05;

// Marks a 3 x 3 voxel wide line of density from a to b (world).
void AddWood(const Eigen::Vector3d& a, const Eigen::Vector3d& b, DensityGrid* density) {
  const int steps = static_cast<int>((b - a).norm() / (0.5 * kVoxel)) + 1;
  for (int s = 0; s <= steps; ++s) {
    const Eigen::Vector3d p = a + (b - a) * (double(s) / steps);
    const Eigen::Vector3i centre = density->IndexFromWorld(p).array().round().cast<int>();
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) density->SetValue(centre + Eigen::Vector3i(i, j, k), 0.5f);
  }
}

// A 10 m trunk with one 3 m branch at 6 m, both in the density; beside the
// branch a second, thinner trace of it 5 cm off; a stick across empty space
// at 8 m; a thin branch leaving the root.
struct Scene {
  SkeletonGraph skeleton;
  DensityGrid density{kVoxel, Eigen::Vector3d::Zero()};
};

Scene MakeScene() {
  Scene scene;
  SkeletonGraph& s = scene.skeleton;
  const int root = s.AddNode({0, 0, 0}, 0, -1, 0);
  const int fork = s.AddNode({0, 0, 6}, 0, root, 0);
  const int upper = s.AddNode({0, 0, 8}, 0, fork, 0);
  s.AddNode({0, 0, 10}, 0, upper, 0);   // 3: trunk top
  s.AddNode({3, 0, 6}, 0, fork, 1);     // 4: the branch
  s.AddNode({3, 0, 6.05}, 0, fork, 1);  // 5: its second trace
  s.AddNode({0, 3, 8}, 0, upper, 1);    // 6: the stick
  s.AddNode({1, 0, 0.5}, 0, root, 1);   // 7: the base twig
  const int strands[] = {100, 98, 68, 66, 20, 10, 2, 2};
  for (int i = 0; i < s.NumNodes(); ++i) s.nodes[i].strands = strands[i];
  s.AssignOrders();
  AddWood({0, 0, 0}, {0, 0, 10}, &scene.density);
  AddWood({0, 0, 6}, {3, 0, 6}, &scene.density);
  AddWood({0, 0, 0}, {1, 0, 0.5}, &scene.density);
  return scene;
}

// Every junction carries the sum of its children (pipe model).
void ExpectStrandsAddUp(const SkeletonGraph& skeleton) {
  const std::vector<std::vector<int>> children = skeleton.Children();
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (children[i].empty()) continue;
    int sum = 0;
    for (int child : children[i]) sum += skeleton.nodes[child].strands;
    EXPECT_EQ(sum, skeleton.nodes[i].strands) << "node " << i;
  }
}

TEST(SkeletonConsolidationTest, KeepsTheWoodTheDensityShowsOnce) {
  const Scene scene = MakeScene();
  ConsolidationSummary summary;
  const SkeletonGraph result =
      ConsolidateSkeleton(scene.skeleton, scene.density, ConsolidationOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NO_THROW(result.Check());
  ASSERT_EQ(result.NumNodes(), 5);
  EXPECT_NEAR(result.TotalLength(), 13.0, 1e-9);
  EXPECT_EQ(summary.trimmed_nodes, 2);  // the second trace and the stick
  EXPECT_EQ(summary.base_axes, 1);
  EXPECT_NEAR(result.nodes[4].position.x(), 3.0, 1e-12);
  // The twin trace's 10 strands move onto the heaviest wood left at the
  // fork (the trunk, out to its top), the stick's 2 onto the trunk top; the
  // base twig's 2 are taken off: every junction carries its children's sum.
  EXPECT_EQ(result.nodes[0].strands, 98);
  EXPECT_EQ(result.nodes[1].strands, 98);
  EXPECT_EQ(result.nodes[2].strands, 78);
  ExpectStrandsAddUp(result);
}

// A limb that flowed beside the trunk (a fifth of a voxel off it) from 2 m
// to 5 m before leaving it: zipped, it leaves the trunk at 6 m, the trunk's
// node nearest to where it parts, and the trunk carries its strands up to
// there. Its node 1 cm off the trunk at 3 m is beyond half a voxel of the
// trunk when the zip radius is a fifth of a voxel, and nothing is zipped.
SkeletonGraph TrunkWithLimbBeside(const Eigen::Vector3d& out_at = {1, 0, 7}) {
  SkeletonGraph s;
  const int root = s.AddNode({0, 0, 0}, 0, -1, 0);
  const int low = s.AddNode({0, 0, 2}, 0, root, 0);
  const int mid = s.AddNode({0, 0, 4}, 0, low, 0);
  const int high = s.AddNode({0, 0, 6}, 0, mid, 0);
  s.AddNode({0, 0, 10}, 0, high, 0);                          // 4: trunk top
  const int beside = s.AddNode({0.01, 0, 3}, 0, low, 1);      // 5
  const int parting = s.AddNode({0.01, 0, 5}, 0, beside, 1);  // 6
  const int out = s.AddNode(out_at, 0, parting, 1);           // 7
  s.AddNode(out_at + Eigen::Vector3d(1, 0, 1), 0, out, 1);    // 8: limb tip
  const int strands[] = {80, 80, 50, 50, 50, 30, 30, 30, 30};
  for (int i = 0; i < s.NumNodes(); ++i) s.nodes[i].strands = strands[i];
  s.AssignOrders();
  return s;
}

// The density of TrunkWithLimbBeside(out_at): the trunk and the limb from
// where it parts.
DensityGrid TrunkAndLimbDensity(const Eigen::Vector3d& out_at = {1, 0, 7}) {
  DensityGrid density(kVoxel, Eigen::Vector3d::Zero());
  AddWood({0, 0, 0}, {0, 0, 10}, &density);
  AddWood({0, 0, 5}, out_at, &density);
  AddWood(out_at, out_at + Eigen::Vector3d(1, 0, 1), &density);
  return density;
}

TEST(SkeletonConsolidationTest, ZipsALimbTracedBesideItsParent) {
  const SkeletonGraph skeleton = TrunkWithLimbBeside();
  const DensityGrid density = TrunkAndLimbDensity();
  ConsolidationSummary summary;
  const SkeletonGraph result =
      ConsolidateSkeleton(skeleton, density, ConsolidationOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NO_THROW(result.Check());
  EXPECT_EQ(summary.zipped_axes, 1);
  ASSERT_EQ(result.NumNodes(), 7);
  EXPECT_NEAR(result.TotalLength(), 10.0 + 2 * std::sqrt(2.0), 1e-9);
  for (int i = 0; i < result.NumNodes(); ++i) {
    EXPECT_LT(result.nodes[i].parent_idx, i) << "parents come first";
  }
  ExpectStrandsAddUp(result);
  // The limb leaves the trunk at 6 m; the trunk carries 80 strands to there.
  for (const SkeletonNode& node : result.nodes) {
    if (node.position.isApprox(Eigen::Vector3d(1, 0, 7))) {
      EXPECT_TRUE(result.nodes[node.parent_idx].position.isApprox(Eigen::Vector3d(0, 0, 6)));
    }
    if (node.position.x() == 0 && node.position.z() > 0 && node.position.z() <= 6) {
      EXPECT_EQ(node.strands, 80) << node.position.z();
    }
  }
  ConsolidationOptions narrow;
  narrow.zip_radius_voxels = 0.1;  // 5 mm: the limb runs 1 cm off the trunk
  ConsolidationSummary kept;
  EXPECT_EQ(ConsolidateSkeleton(skeleton, density, narrow, &kept).NumNodes(), 9);
  EXPECT_EQ(kept.zipped_axes, 0);
}

// Where the limb parts nearest the trunk's tip, it joins the node below:
// the tip's strands are the particles that started there, and it would
// carry a child's without their sum.
TEST(SkeletonConsolidationTest, ZippedLimbsDoNotJoinTheParentsTip) {
  const SkeletonGraph skeleton = TrunkWithLimbBeside({1, 0, 9.5});
  ConsolidationSummary summary;
  const SkeletonGraph result = ConsolidateSkeleton(skeleton, TrunkAndLimbDensity({1, 0, 9.5}),
                                                   ConsolidationOptions(), &summary);
  EXPECT_EQ(summary.zipped_axes, 1);
  const std::vector<std::vector<int>> children = result.Children();
  for (int i = 0; i < result.NumNodes(); ++i) {
    if (result.nodes[i].position.isApprox(Eigen::Vector3d(0, 0, 10))) {
      EXPECT_TRUE(children[i].empty());
      EXPECT_EQ(result.nodes[i].strands, 50);
    }
    if (result.nodes[i].position.isApprox(Eigen::Vector3d(1, 0, 9.5))) {
      EXPECT_TRUE(
          result.nodes[result.nodes[i].parent_idx].position.isApprox(Eigen::Vector3d(0, 0, 6)));
    }
  }
  ExpectStrandsAddUp(result);
}

// A twig that grew from the limb where the limb ran beside the trunk grew
// from the trunk's wood: when the limb is zipped, the twig joins the trunk
// at the height it grew at (a node splitting the trunk's edge there), and
// the trunk carries its strands up to there.
TEST(SkeletonConsolidationTest, TwigsOfAZippedStretchMoveToTheParent) {
  SkeletonGraph skeleton = TrunkWithLimbBeside();
  const Eigen::Vector3d twig_tip(-1, 0, 3.5);
  skeleton.AddNode(twig_tip, 0, 5, 2);  // from the limb at 3 m
  const int strands[] = {85, 85, 50, 50, 50, 35, 30, 30, 30, 5};
  for (int i = 0; i < skeleton.NumNodes(); ++i) skeleton.nodes[i].strands = strands[i];
  skeleton.AssignOrders();
  ExpectStrandsAddUp(skeleton);
  DensityGrid density = TrunkAndLimbDensity();
  AddWood(skeleton.nodes[5].position, twig_tip, &density);
  ConsolidationSummary summary;
  const SkeletonGraph result =
      ConsolidateSkeleton(skeleton, density, ConsolidationOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NO_THROW(result.Check());
  EXPECT_EQ(summary.zipped_axes, 1);
  ASSERT_EQ(result.NumNodes(), 9);  // 10, less the limb's 2 beside the trunk, plus the split
  ExpectStrandsAddUp(result);
  for (int i = 0; i < result.NumNodes(); ++i) {
    EXPECT_LT(result.nodes[i].parent_idx, i) << "parents come first";
    const SkeletonNode& node = result.nodes[i];
    if (node.position.isApprox(twig_tip)) {
      EXPECT_TRUE(result.nodes[node.parent_idx].position.isApprox(Eigen::Vector3d(0, 0, 3)));
      EXPECT_EQ(node.strands, 5);
    }
  }
  // The trunk: 85 to 3 m (trunk, limb and twig), 80 to 6 m (trunk and limb).
  for (const SkeletonNode& node : result.nodes) {
    if (node.position.x() != 0 || node.position.z() == 10) continue;
    EXPECT_EQ(node.strands, node.position.z() <= 3 ? 85 : 80) << node.position.z();
  }
}

// Two limbs of a 10 m trunk: A (30 strands) leaves it at 4 m and rises at
// x = 2 m from 5 m to 8 m; B (10 strands) leaves it at 6 m, runs 3 cm beside
// A from 6.5 m to 7.8 m, and parts again to its own tip: A traced twice.
SkeletonGraph TrunkWithTwoLimbsSideBySide() {
  SkeletonGraph s;
  const int root = s.AddNode({0, 0, 0}, 0, -1, 0);
  const int fork_a = s.AddNode({0, 0, 4}, 0, root, 0);
  const int fork_b = s.AddNode({0, 0, 6}, 0, fork_a, 0);
  s.AddNode({0, 0, 10}, 0, fork_b, 0);  // 3: trunk top
  int k = fork_a;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(2, 0, 5), Eigen::Vector3d(2, 0, 8), Eigen::Vector3d(3, 0, 9)}) {
    k = s.AddNode(p, 0, k, 1);  // 4-6: limb A
  }
  k = fork_b;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(2.03, 0, 6.5), Eigen::Vector3d(2.03, 0, 7.8), Eigen::Vector3d(1, 0, 9.5)}) {
    k = s.AddNode(p, 0, k, 1);  // 7-9: limb B
  }
  const int strands[] = {100, 100, 70, 60, 30, 30, 30, 10, 10, 10};
  for (int i = 0; i < s.NumNodes(); ++i) s.nodes[i].strands = strands[i];
  s.AssignOrders();
  return s;
}

TEST(SkeletonConsolidationTest, JoinsAStretchTracedBesideOtherWood) {
  const SkeletonGraph skeleton = TrunkWithTwoLimbsSideBySide();
  DensityGrid density(kVoxel, Eigen::Vector3d::Zero());
  for (int i = 1; i < skeleton.NumNodes(); ++i) {
    AddWood(skeleton.nodes[skeleton.nodes[i].parent_idx].position, skeleton.nodes[i].position,
            &density);
  }
  // Off by default: every node stays.
  ConsolidationSummary kept;
  EXPECT_EQ(ConsolidateSkeleton(skeleton, density, ConsolidationOptions(), &kept).NumNodes(),
            skeleton.NumNodes());
  EXPECT_EQ(kept.joined_duplicates, 0);

  ConsolidationOptions options;
  options.duplicate_radius_voxels = 1.0;  // 5 cm
  ConsolidationSummary summary;
  const SkeletonGraph result = ConsolidateSkeleton(skeleton, density, options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NO_THROW(result.Check());
  EXPECT_EQ(summary.joined_duplicates, 1);
  for (int i = 0; i < result.NumNodes(); ++i) {
    EXPECT_LT(result.nodes[i].parent_idx, i) << "parents come first";
  }
  ExpectStrandsAddUp(result);
  EXPECT_EQ(result.nodes[result.RootIdx()].strands, 100);
  // B's way to A and its stretch beside A are gone (2.09 m + 1.3 m, and the
  // first 10-15 cm of its way out, still within 5 cm of A); its free part
  // now grows from A, which carries its strands down to the trunk.
  EXPECT_NEAR(skeleton.TotalLength() - result.TotalLength(), std::hypot(2.03, 0.5) + 1.42, 0.06);
  int tip = -1;
  for (int i = 0; i < result.NumNodes(); ++i) {
    const Eigen::Vector3d& p = result.nodes[i].position;
    EXPECT_FALSE(p.x() > 2.01 && p.z() > 6.0 && p.z() < 7.7) << "a node of B's stretch stays";
    if (p.isApprox(Eigen::Vector3d(1, 0, 9.5))) tip = i;
  }
  ASSERT_GE(tip, 0) << "B's tip is gone";
  bool through_a = false;
  for (int k = tip; k >= 0; k = result.nodes[k].parent_idx) {
    const Eigen::Vector3d& p = result.nodes[k].position;
    if (std::abs(p.x() - 2.0) < 1e-9 && p.z() > 7.0 && p.z() <= 8.0) {
      through_a = true;
      EXPECT_EQ(result.nodes[k].strands, 40);
    }
    if (p.x() == 0 && p.z() > 4 && p.z() <= 6) {
      EXPECT_EQ(result.nodes[k].strands, 60);
    }
  }
  EXPECT_TRUE(through_a);

  // Where the skeleton does not count strands (0: unknown), nothing joins.
  SkeletonGraph uncounted = skeleton;
  for (SkeletonNode& node : uncounted.nodes) node.strands = 0;
  ConsolidationSummary unjoined;
  EXPECT_EQ(ConsolidateSkeleton(uncounted, density, options, &unjoined).NumNodes(),
            ConsolidateSkeleton(uncounted, density, ConsolidationOptions(), nullptr).NumNodes());
  EXPECT_EQ(unjoined.joined_duplicates, 0);
}

// Step 5: a twig lying inside the trunk's radius goes (its strands move on
// down the trunk); one that leaves the trunk stays, and so does one inside
// wood thinner than itself.
TEST(SkeletonConsolidationTest, RemovesTwigsHiddenInsideThickerWood) {
  SkeletonGraph s;
  const int root = s.AddNode({0, 0, 0}, 0.5, -1, 0);
  const int low = s.AddNode({0, 0, 4}, 0.5, root, 0);
  const int high = s.AddNode({0, 0, 8}, 0.4, low, 0);
  const int top = s.AddNode({0, 0, 10}, 0.3, high, 0);
  const int stub = s.AddNode({0.3, 0, 5}, 0.05, low, 1);    // inside the trunk
  const int branch = s.AddNode({3, 0, 6}, 0.1, low, 1);     // leaves it
  const int fat = s.AddNode({0.2, 0.1, 9}, 0.35, high, 1);  // inside, but thicker
  const int strands[] = {100, 100, 90, 80, 5, 5, 10};
  for (int i = 0; i < s.NumNodes(); ++i) s.nodes[i].strands = strands[i];
  s.AssignOrders();
  ExpectStrandsAddUp(s);
  SkeletonGraph result = s;
  EXPECT_EQ(RemoveHiddenTwigs(0.05, &result), 1);
  ASSERT_EQ(result.NumNodes(), s.NumNodes() - 1);
  // Strands of the node at `node`'s position in the result.
  const auto strands_at = [&](int node) {
    for (const SkeletonNode& kept : result.nodes) {
      if (kept.position == s.nodes[node].position) return kept.strands;
    }
    return -1;
  };
  EXPECT_EQ(strands_at(stub), -1) << "the hidden stub was kept";
  ExpectStrandsAddUp(result);
  EXPECT_EQ(result.nodes[result.RootIdx()].strands, 100);
  // The stub's 5 strands went on up the heaviest child (the trunk) to its
  // heaviest tip.
  EXPECT_EQ(strands_at(high), 95);
  EXPECT_EQ(strands_at(top), 85);
  EXPECT_EQ(strands_at(branch), 5);
  EXPECT_EQ(strands_at(fat), 10);
  // Nothing left to hide: a second call removes nothing.
  EXPECT_EQ(RemoveHiddenTwigs(0.05, &result), 0);
}

TEST(SkeletonConsolidationTest, DisabledStepsKeepEverything) {
  const Scene scene = MakeScene();
  const SkeletonGraph result =
      ConsolidateSkeleton(scene.skeleton, scene.density, ConsolidationOptions::Off(), nullptr);
  EXPECT_EQ(result.NumNodes(), scene.skeleton.NumNodes());
  EXPECT_NEAR(result.TotalLength(), scene.skeleton.TotalLength(), 1e-9);
}

TEST(SkeletonConsolidationTest, RejectsBadOptions) {
  ConsolidationOptions options;
  options.min_support = 2;
  EXPECT_THROW(options.Check(), InputError);
  options = ConsolidationOptions();
  options.zip_radius_voxels = -1;
  EXPECT_THROW(options.Check(), InputError);
  options = ConsolidationOptions();
  options.duplicate_radius_voxels = 9;
  EXPECT_THROW(options.Check(), InputError);
}

}  // namespace
}  // namespace sylva
