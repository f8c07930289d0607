#include "simulate/skeleton_consolidation.h"

#include <gtest/gtest.h>

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
  const std::vector<std::vector<int>> children = result.Children();
  for (int i = 0; i < result.NumNodes(); ++i) {
    if (children[i].empty()) continue;
    int sum = 0;
    for (int child : children[i]) sum += result.nodes[child].strands;
    EXPECT_EQ(sum, result.nodes[i].strands) << "node " << i;
  }
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
}

}  // namespace
}  // namespace sylva
