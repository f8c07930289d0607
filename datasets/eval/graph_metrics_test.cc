#include "datasets/eval/graph_metrics.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

// A trunk (order 0), a branch (order 1) and a twig (order 2), in metres.
SkeletonGraph SmallSkeleton() {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0.1, -1, 0);
  const int fork = skeleton.AddNode({0, -1, 0}, 0.1, root, 0);
  const int branch = skeleton.AddNode({1, -1, 0}, 0.05, fork, 1);
  skeleton.AddNode({1, -2, 0}, 0.02, branch, 2);
  return skeleton;
}

ImageSet OneView(const Camera& camera, const Eigen::Vector3d& translation) {
  ImageSet image_set;
  image_set.cameras.emplace(1, camera);
  View view;
  view.image_id = 1;
  view.name = "view.png";
  view.camera_id = 1;
  view.cam_from_world.translation = translation;
  image_set.views.push_back(view);
  return image_set;
}

TEST(ProjectSkeletonTest, OrthographicKeepsLowOrdersAndParents) {
  const ImageSet image_set = OneView(Camera::Orthographic(100, 80, 10.0), Eigen::Vector3d::Zero());
  const AttractorGraph2D graph = ProjectSkeleton(SmallSkeleton(), image_set, 0, 1);
  graph.Check("projected");
  ASSERT_EQ(graph.NumNodes(), 3);
  EXPECT_EQ(graph.width, 100);
  EXPECT_EQ(graph.height, 80);
  EXPECT_EQ(graph.NumEdges(), 2);
  ASSERT_EQ(graph.root, 0);
  EXPECT_NEAR((graph.nodes[0].position - Eigen::Vector2d(50, 40)).norm(), 0, 1e-9);
  EXPECT_NEAR((graph.nodes[2].position - Eigen::Vector2d(60, 30)).norm(), 0, 1e-9);
  EXPECT_EQ(graph.nodes[2].parent_idx, 1);
  EXPECT_EQ(ProjectSkeleton(SmallSkeleton(), image_set, 0, 2).NumNodes(), 4);
}

TEST(ProjectSkeletonTest, PinholeAndBehindCamera) {
  const ImageSet front = OneView(Camera::Pinhole(100, 100, 50.0), Eigen::Vector3d(0, 0, 5));
  const AttractorGraph2D graph = ProjectSkeleton(SmallSkeleton(), front, 0, 0);
  ASSERT_EQ(graph.NumNodes(), 2);
  EXPECT_NEAR((graph.nodes[1].position - Eigen::Vector2d(50, 40)).norm(), 0, 1e-9);
  const ImageSet behind = OneView(Camera::Pinhole(100, 100, 50.0), Eigen::Vector3d(0, 0, -5));
  EXPECT_THROW(ProjectSkeleton(SmallSkeleton(), behind, 0, 0), InputError);
}

TEST(CompareGraphs2DTest, ParallelSegmentsAreTheirOffsetApart) {
  AttractorGraph2D a, b;
  a.width = b.width = a.height = b.height = 100;
  a.root = a.AddNode({10, 20}, -1);
  a.AddNode({60, 20}, a.root);
  b.root = b.AddNode({10, 23}, -1);
  b.AddNode({60, 23}, b.root);
  const PointSetDistances d = CompareGraphs2D(a, b, 1.0);
  EXPECT_NEAR(d.chamfer, 3.0, 1e-9);
  EXPECT_NEAR(d.hausdorff, 3.0, 1e-9);
  // Against half of b's samples: a's far end is 25 px from them.
  std::vector<Eigen::Vector2d> half;
  for (int x = 10; x <= 35; ++x) half.emplace_back(x, 23);
  const PointSetDistances to_half = CompareGraphs2D(a, half, 1.0);
  EXPECT_NEAR(to_half.mean_b_to_a, 3.0, 1e-9);
  EXPECT_GT(to_half.mean_a_to_b, 5.0);
}

}  // namespace
}  // namespace sylva
