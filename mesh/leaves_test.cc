#include "mesh/leaves.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

// A trunk up to z = 4 forking into two thin branches, x < 0 and x > 0.
SkeletonGraph TwoBranchTree() {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int fork = skeleton.AddNode({0, 0, 4}, 0.2, root, 0);
  const int left = skeleton.AddNode({-2, 0, 6}, 0.05, fork, 1);
  const int right = skeleton.AddNode({2, 0, 6}, 0.05, fork, 1);
  skeleton.AddNode({-2.5, 0, 7}, 0.04, left, 1);
  skeleton.AddNode({2.5, 0, 7}, 0.04, right, 1);
  return skeleton;
}

// Two blobs of voxels around the branches; the left one 3x as opaque.
DensityGrid TwoBlobs() {
  DensityGrid grid(0.1, Eigen::Vector3d::Zero());
  for (int k = 55; k <= 70; ++k)
    for (int j = -5; j <= 5; ++j)
      for (int i = 15; i <= 25; ++i) {
        grid.SetValue({-i, j, k}, 0.6f);
        grid.SetValue({i, j, k}, 0.2f);
      }
  return grid;
}

// One orthographic view looking along +y, seeing x in [-5, 5] and z in [0, 10].
ImageSet FrontView() {
  ImageSet set;
  set.cameras[1] = Camera(CameraModel::kOrthographic, 100, 100, {10, 10, 50, 50});
  View view;
  view.image_id = 1;
  view.name = "front.png";
  view.camera_id = 1;
  view.cam_from_world = LookAt({0, -10, 5}, {0, 0, 5}, Eigen::Vector3d::UnitZ());
  set.views.push_back(view);
  return set;
}

double MeanAbsDot(const TriangleMesh& mesh, const Eigen::Vector3d& center) {
  double sum = 0.0;
  for (int t = 0; t < mesh.NumTriangles(); t += 2) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    sum += std::abs(n.dot(((a + c) / 2 - center).normalized()));
  }
  return sum / (mesh.NumTriangles() / 2);
}

TEST(LeavesTest, CountSizeAndDensityProportion) {
  LeafOptions options;
  options.num_leaves = 4000;
  options.leaf_length = 0.1;
  options.twig_reach = 20.0;  // every blob voxel is within 2 m of a branch
  LeafSummary summary;
  const TriangleMesh mesh =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.drawn, 4000);
  EXPECT_EQ(summary.kept, 4000);
  EXPECT_EQ(mesh.NumTriangles(), 2 * summary.kept);
  EXPECT_EQ(mesh.materials[0].name, "leaves");
  EXPECT_TRUE(mesh.materials[0].double_sided);
  int left = 0, right = 0;
  for (int q = 0; q < summary.kept; ++q) {
    const Eigen::Vector3f base = mesh.vertices[4 * q], tip = mesh.vertices[4 * q + 2];
    EXPECT_NEAR((tip - base).norm(), 0.1f, 1e-5f);
    ((base.x() + tip.x()) < 0 ? left : right)++;
  }
  // Drawn in proportion to opacity: 0.6 vs 0.2.
  EXPECT_NEAR(static_cast<double>(left) / right, 3.0, 0.45);
}

TEST(LeavesTest, LeavesFarFromThinBranchesAreDropped) {
  LeafOptions options;
  options.num_leaves = 2000;
  options.leaf_length = 0.1;
  options.twig_reach = 0.5;  // only leaves within 5 cm of a branch
  LeafSummary summary;
  GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, &summary);
  EXPECT_GT(summary.far_from_branches, summary.kept);
}

TEST(LeavesTest, PhototropismTurnsLeavesOutward) {
  LeafOptions options;
  options.num_leaves = 3000;
  options.leaf_length = 0.1;
  options.phototropism = 0.0;
  const DensityGrid density = TwoBlobs();
  const TriangleMesh random = GenerateLeaves(TwoBranchTree(), density, ImageSet(), {}, options, nullptr);
  options.phototropism = 1.0;
  const TriangleMesh turned = GenerateLeaves(TwoBranchTree(), density, ImageSet(), {}, options, nullptr);
  // The density-weighted centre of the two blobs.
  const Eigen::Vector3d center(-1.0, 0.0, 6.25);
  EXPECT_GT(MeanAbsDot(turned, center), MeanAbsDot(random, center) + 0.15);
}

TEST(LeavesTest, LeavesOutsideTheMattesAreDropped) {
  FloatImage matte(100, 100, 1, 1.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 50; x < 100; ++x) matte.at(x, y) = 0.0f;  // x > 0 is empty
  LeafOptions options;
  options.num_leaves = 2000;
  options.leaf_length = 0.1;
  LeafSummary summary;
  const TriangleMesh mesh =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), FrontView(), {matte}, options, &summary);
  EXPECT_GT(summary.outside_mattes, 100);
  for (const Eigen::Vector3f& v : mesh.vertices) EXPECT_LT(v.x(), 0.2f);
}

TEST(LeavesTest, DeterministicAndOptionsChecked) {
  LeafOptions options;
  options.num_leaves = 500;
  const TriangleMesh a = GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  const TriangleMesh b = GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  EXPECT_EQ(a.vertices, b.vertices);
  options.seed = 2;
  const TriangleMesh c = GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  EXPECT_NE(a.vertices, c.vertices);
  options.leaf_aspect = -1;
  try {
    GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Leaves.leaf_aspect");
  }
}

}  // namespace
}  // namespace sylva
