#include "simulate/skeleton_pruning.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

// A trunk (100 strands) with two laterals: one inside the crown (x < 0,
// 3 strands, with a sub-branch of 1), one leaving it (x > 0, 2 strands).
SkeletonGraph Tree() {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0, -1, 0);
  const int fork = skeleton.AddNode({0, 0, 4}, 0, root, 0);
  const int top = skeleton.AddNode({0, 0, 8}, 0, fork, 0);
  const int inside = skeleton.AddNode({-2, 0, 6}, 0, fork, 1);
  const int inside_tip = skeleton.AddNode({-3, 0, 7}, 0, inside, 1);
  const int sub = skeleton.AddNode({-2.5, 0, 7.5}, 0, inside, 2);
  const int outside = skeleton.AddNode({3, 0, 5}, 0, fork, 1);
  const int outside_tip = skeleton.AddNode({4, 0, 6}, 0, outside, 1);
  const int strands[] = {100, 100, 95, 3, 2, 1, 2, 2};
  for (int i = 0; i < 8; ++i) skeleton.nodes[i].strands = strands[i];
  (void)top, (void)inside_tip, (void)sub, (void)outside_tip;
  return skeleton;
}

// One orthographic view along +y whose matte covers x < 0.5 only.
void FrontView(ImageSet* views, std::vector<FloatImage>* mattes) {
  views->cameras[1] = Camera(CameraModel::kOrthographic, 100, 100, {10, 10, 50, 50});
  View view;
  view.image_id = 1;
  view.name = "front.png";
  view.camera_id = 1;
  view.cam_from_world = LookAt({0, -10, 5}, {0, 0, 5}, Eigen::Vector3d::UnitZ());
  views->views.push_back(view);
  FloatImage matte(100, 100, 1, 0.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 55; ++x) matte.at(x, y) = 1.0f;  // pixel x < 55 <-> world x < 0.5
  mattes->push_back(matte);
}

TEST(SkeletonPruningTest, RemovesTheBranchLeavingTheMatteAndItsStrands) {
  ImageSet views;
  std::vector<FloatImage> mattes;
  FrontView(&views, &mattes);
  MattePruningSummary summary;
  const SkeletonGraph pruned =
      PruneBranchesOutsideMattes(Tree(), views, mattes, MattePruningOptions(), &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.tested_axes, 3);  // both laterals and the sub-branch (trunk is thick)
  EXPECT_EQ(summary.removed_axes, 1);
  EXPECT_EQ(summary.removed_nodes, 2);
  EXPECT_EQ(summary.removed_strands, 2);
  ASSERT_EQ(pruned.NumNodes(), 6);
  EXPECT_NO_THROW(pruned.Check());
  for (const SkeletonNode& node : pruned.nodes) EXPECT_LT(node.position.x(), 0.5);
  // Strands stay consistent: root and fork lose the 2 removed ones.
  EXPECT_EQ(pruned.nodes[0].strands, 98);
  EXPECT_EQ(pruned.nodes[1].strands, 98);
  const std::vector<std::vector<int>> children = pruned.Children();
  for (int i = 0; i < pruned.NumNodes(); ++i) {
    if (children[i].empty()) continue;
    int sum = 0;
    for (int c : children[i]) sum += pruned.nodes[c].strands;
    EXPECT_EQ(sum, pruned.nodes[i].strands) << "node " << i;
  }
}

TEST(SkeletonPruningTest, ThickBranchesAndDisabledPruningAreKept) {
  ImageSet views;
  std::vector<FloatImage> mattes;
  FrontView(&views, &mattes);
  MattePruningOptions options;
  options.max_strand_fraction = 0.01;  // the 2-strand branch counts as thick
  EXPECT_EQ(PruneBranchesOutsideMattes(Tree(), views, mattes, options, nullptr).NumNodes(), 8);
  options.max_strand_fraction = 0.0;
  EXPECT_EQ(PruneBranchesOutsideMattes(Tree(), views, mattes, options, nullptr).NumNodes(), 8);
  options.max_outside_fraction = 1.5;
  EXPECT_THROW(PruneBranchesOutsideMattes(Tree(), views, mattes, options, nullptr), InputError);
}

}  // namespace
}  // namespace sylva
