#include "mesh/leaves.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "mesh/phyllotaxis.h"

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
  const TriangleMesh random =
      GenerateLeaves(TwoBranchTree(), density, ImageSet(), {}, options, nullptr);
  options.phototropism = 1.0;
  const TriangleMesh turned =
      GenerateLeaves(TwoBranchTree(), density, ImageSet(), {}, options, nullptr);
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
  const TriangleMesh a =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  const TriangleMesh b =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  EXPECT_EQ(a.vertices, b.vertices);
  options.seed = 2;
  const TriangleMesh c =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  EXPECT_NE(a.vertices, c.vertices);
  options.leaf_aspect = -1;
  try {
    GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Leaves.leaf_aspect");
  }
}

// A trunk to z = 1 continued by a thin straight shoot to z = 3.
SkeletonGraph Shoot() {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int top = skeleton.AddNode({0, 0, 1}, 0.2, root, 0);
  const int mid = skeleton.AddNode({0, 0, 2}, 0.03, top, 0);
  skeleton.AddNode({0, 0, 3}, 0.02, mid, 0);
  return skeleton;
}

// Opacity `lower` around the shoot below z = 2, `upper` above.
DensityGrid ShootDensity(float lower, float upper) {
  DensityGrid grid(0.1, Eigen::Vector3d::Zero());
  for (int k = 10; k <= 31; ++k)
    for (int j = -2; j <= 2; ++j)
      for (int i = -2; i <= 2; ++i) grid.SetValue({i, j, k}, k < 20 ? lower : upper);
  return grid;
}

// Petiole directions of the leaves (their +X), projected on the XY plane
// (the shoot runs along Z), ordered up the shoot.
std::vector<LeafAttachment> AsAttachments(const LeafInstances& leaves) {
  std::vector<LeafAttachment> out;
  for (const LeafInstance& leaf : leaves.instances) {
    LeafAttachment a;
    a.position = leaf.translation.cast<double>();
    a.petiole_direction = (leaf.rotation * Eigen::Vector3f::UnitX()).cast<double>();
    a.axis_tangent = Eigen::Vector3d::UnitZ();
    out.push_back(a);
  }
  std::stable_sort(out.begin(), out.end(), [](const LeafAttachment& a, const LeafAttachment& b) {
    return a.position.z() < b.position.z() - 1e-6;
  });
  return out;
}

double MeanDivergence(const std::vector<LeafAttachment>& leaves, int step) {
  double sum = 0.0;
  int count = 0;
  for (size_t i = 0; i + step < leaves.size(); i += step, ++count) {
    sum += DivergenceAngleDeg(leaves[i], leaves[i + step]);
  }
  return sum / count;
}

TEST(LeavesTest, PhyllotaxisPatternsAlongAShoot) {
  LeafOptions options;
  options.num_leaves = 100000;  // more than the sites: every site is kept
  options.leaf_length = 0.05;
  options.phototropism = 0.3;
  options.phyllotaxis = "spiral";
  LeafSummary summary;
  LeafInstances leaves =
      GenerateLeafInstances(Shoot(), ShootDensity(0.5f, 0.5f), ImageSet(), {}, options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  // Nodes every 0.6 leaf lengths on the 2 m thin shoot.
  EXPECT_NEAR(summary.phyllotaxis_sites, 2.0 / 0.03, 1.0);
  EXPECT_EQ(summary.kept, summary.phyllotaxis_sites);
  std::vector<LeafAttachment> measured = AsAttachments(leaves);
  EXPECT_NEAR(MeanDivergence(measured, 1), 137.5, 1.0);
  for (const LeafAttachment& a : measured) {
    EXPECT_NEAR(a.position.head<2>().norm(), 0.0, 1e-5);  // leaf bases on the shoot
    EXPECT_NEAR(a.petiole_direction.z(), std::cos(60.0 * M_PI / 180), 1e-5);
  }

  options.phyllotaxis = "alternate";
  leaves =
      GenerateLeafInstances(Shoot(), ShootDensity(0.5f, 0.5f), ImageSet(), {}, options, nullptr);
  EXPECT_NEAR(MeanDivergence(AsAttachments(leaves), 1), 180.0, 1.0);

  options.phyllotaxis = "opposite_decussate";
  leaves =
      GenerateLeafInstances(Shoot(), ShootDensity(0.5f, 0.5f), ImageSet(), {}, options, nullptr);
  measured = AsAttachments(leaves);
  ASSERT_EQ(measured.size() % 2, 0u);
  EXPECT_NEAR(MeanDivergence(measured, 2), 90.0, 1.0);
  EXPECT_NEAR(DivergenceAngleDeg(measured[0], measured[1]), 180.0, 1e-3);

  options.phyllotaxis = "whorled";
  options.leaves_per_whorl = 3;
  leaves =
      GenerateLeafInstances(Shoot(), ShootDensity(0.5f, 0.5f), ImageSet(), {}, options, nullptr);
  measured = AsAttachments(leaves);
  EXPECT_NEAR(MeanDivergence(measured, 3), 60.0, 1.0);
  EXPECT_NEAR(DivergenceAngleDeg(measured[0], measured[1]), 120.0, 1e-3);
}

TEST(LeavesTest, PhyllotacticLeavesKeepTheDensityDrivenCount) {
  LeafOptions options;
  options.leaf_length = 0.01;  // 333 sites on the 2 m thin shoot
  options.num_leaves = 200;
  options.phyllotaxis = "spiral";
  LeafSummary summary;
  const LeafInstances leaves =
      GenerateLeafInstances(Shoot(), ShootDensity(0.6f, 0.2f), ImageSet(), {}, options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NEAR(summary.phyllotaxis_sites, 333, 1);
  EXPECT_NEAR(summary.kept, 200, 45);
  int lower = 0, upper = 0;
  for (const LeafInstance& leaf : leaves.instances) (leaf.translation.z() < 2.0f ? lower : upper)++;
  EXPECT_NEAR(static_cast<double>(lower) / upper, 3.0, 1.0);
  // The shape is the quad: 2 triangles per leaf once baked.
  EXPECT_EQ(leaves.Bake().NumTriangles(), 2 * summary.kept);
}

// Trees known by their skeleton alone: the leaves sit on the bark at the
// pattern's sites of the thin shoot (all of them, or num_leaves chosen), or
// spread along it without phyllotaxis; none for num_leaves = -1; same seed, same
// leaves.
TEST(LeavesTest, SkeletonLeavesFollowTheThinBranchesAlone) {
  LeafOptions options;
  options.leaf_length = 0.05;
  options.phyllotaxis = "spiral";
  LeafSummary summary;
  LeafInstances leaves = GenerateSkeletonLeafInstances(Shoot(), options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_NE(summary.BriefReport().find("spiral phyllotaxis"), std::string::npos);
  // Nodes every 0.6 leaf lengths on the 2 m thin shoot, every one kept.
  EXPECT_NEAR(summary.phyllotaxis_sites, 2.0 / 0.03, 1.0);
  EXPECT_EQ(summary.kept, summary.phyllotaxis_sites);
  EXPECT_EQ(static_cast<int64_t>(leaves.instances.size()), summary.kept);
  const std::vector<LeafAttachment> measured = AsAttachments(leaves);
  EXPECT_NEAR(MeanDivergence(measured, 1), 137.5, 1.0);
  // On the thin shoot's bark: radius 0.03 below z = 2, 0.02 above.
  auto bark_radius = [](const LeafAttachment& a) { return a.position.z() < 2.0 ? 0.03 : 0.02; };
  for (const LeafAttachment& a : measured) {
    EXPECT_NEAR(a.position.head<2>().norm(), bark_radius(a), 1e-5);
    EXPECT_GE(a.position.z(), 1.0 - 1e-5);
  }
  const LeafInstances again = GenerateSkeletonLeafInstances(Shoot(), options, nullptr);
  ASSERT_EQ(again.instances.size(), leaves.instances.size());
  for (size_t i = 0; i < leaves.instances.size(); ++i) {
    EXPECT_EQ(again.instances[i].translation, leaves.instances[i].translation);
    EXPECT_EQ(again.instances[i].rotation.coeffs(), leaves.instances[i].rotation.coeffs());
  }

  options.num_leaves = 20;  // 20 of the sites, in their order up the shoot
  leaves = GenerateSkeletonLeafInstances(Shoot(), options, &summary);
  ASSERT_EQ(leaves.instances.size(), 20u);
  for (size_t i = 1; i < leaves.instances.size(); ++i) {
    EXPECT_GT(leaves.instances[i].translation.z(), leaves.instances[i - 1].translation.z());
  }

  options.num_leaves = 0;
  options.phyllotaxis = "none";  // one per internode, spread along the shoot
  leaves = GenerateSkeletonLeafInstances(Shoot(), options, &summary);
  EXPECT_NEAR(static_cast<double>(leaves.instances.size()), 2.0 / 0.03, 1.0);
  for (const LeafAttachment& a : AsAttachments(leaves)) {
    EXPECT_NEAR(a.position.head<2>().norm(), bark_radius(a), 1e-5);
    EXPECT_GE(a.position.z(), 1.0 - 1e-5);
    EXPECT_NEAR(a.petiole_direction.z(), std::cos(60.0 * M_PI / 180), 1e-5);
  }
  options.seed = 2;
  const LeafInstances other = GenerateSkeletonLeafInstances(Shoot(), options, nullptr);
  EXPECT_NE(other.instances[0].translation, leaves.instances[0].translation);

  options.num_leaves = -1;
  EXPECT_TRUE(GenerateSkeletonLeafInstances(Shoot(), options, nullptr).instances.empty());
}

double ShapeArea(const LeafShape& shape) {
  double area = 0.0;
  for (const Eigen::Vector3i& t : shape.triangles) {
    const Eigen::Vector2f a = shape.points[t[1]] - shape.points[t[0]];
    const Eigen::Vector2f b = shape.points[t[2]] - shape.points[t[0]];
    const double signed_area = 0.5 * (a.x() * b.y() - a.y() * b.x());
    EXPECT_GT(signed_area, 0.0) << shape.name;  // counter-clockwise from +Z
    area += signed_area;
  }
  return area;
}

TEST(LeavesTest, BuiltinShapesAndImageLeaves) {
  EXPECT_NEAR(ShapeArea(BuiltinLeafShape("quad", 0.6)), 0.3, 1e-6);
  const double ovate = ShapeArea(BuiltinLeafShape("ovate", 0.6));
  const double lanceolate = ShapeArea(BuiltinLeafShape("lanceolate", 0.6));
  EXPECT_GT(ovate, 0.6 * 0.55);  // fuller than the rhombus
  EXPECT_LT(ovate, 0.6 * 0.8);
  EXPECT_LT(lanceolate, ovate);
  EXPECT_NEAR(ShapeArea(BuiltinLeafShape("needle", 0.6)), 0.025, 1e-6);
  for (const char* name : {"ovate", "lanceolate"}) {
    const LeafShape shape = BuiltinLeafShape(name, 0.6);
    EXPECT_EQ(shape.triangles.size(), 14u);
    for (const Eigen::Vector2f& p : shape.points) {
      EXPECT_GE(p.x(), 0.0f);
      EXPECT_LE(p.x(), 1.0f);
      EXPECT_LE(std::abs(p.y()), 0.3f + 1e-6f);
    }
  }
  EXPECT_THROW(BuiltinLeafShape("maple", 0.6), InputError);

  // An image with the leaf's alpha in columns 5..14 of 20, all 40 rows.
  FloatImage image(20, 40, 4, 0.0f);
  for (int y = 0; y < 40; ++y)
    for (int x = 5; x < 15; ++x) image.at(x, y, 3) = 1.0f;
  const LeafShape textured = LeafShapeFromImage(image, "leaf.png");
  textured.Check();
  EXPECT_NEAR(ShapeArea(textured), 0.25, 1e-6);              // 10 x 40 pixels: width / length 1 / 4
  EXPECT_EQ(textured.uvs[0], Eigen::Vector2f(0.75f, 1.0f));  // base, -Y: bottom right
  EXPECT_EQ(textured.uvs[2], Eigen::Vector2f(0.25f, 0.0f));  // tip, +Y: top left
  try {
    LeafShapeFromImage(FloatImage(4, 4, 3, 1.0f), "leaf.jpg");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "leaf.jpg");
  }
  EXPECT_THROW(LeafShapeFromImage(FloatImage(4, 4, 4, 0.0f), "empty.png"), InputError);

  // Generated with an image shape: same instances as with the quad, 2 triangles each.
  LeafOptions options;
  options.num_leaves = 50;
  const LeafInstances quads =
      GenerateLeafInstances(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  const LeafInstances images = GenerateLeafInstances(TwoBranchTree(), TwoBlobs(), ImageSet(), {},
                                                     options, nullptr, &textured);
  ASSERT_EQ(quads.instances.size(), images.instances.size());
  EXPECT_EQ(images.shape.texture.width(), 20);
  const int n = static_cast<int>(quads.instances.size());
  EXPECT_GT(n, 20);
  EXPECT_EQ(images.Bake().NumTriangles(), 2 * n);
  options.shape = "ovate";
  const TriangleMesh ovate_mesh =
      GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr);
  EXPECT_EQ(ovate_mesh.NumTriangles(), n * 14);
  // Baked leaves face their instance's normal (+Z of the leaf frame).
  const Eigen::Vector3f n0 = (ovate_mesh.vertices[ovate_mesh.triangles[0][1]] -
                              ovate_mesh.vertices[ovate_mesh.triangles[0][0]])
                                 .cross(ovate_mesh.vertices[ovate_mesh.triangles[0][2]] -
                                        ovate_mesh.vertices[ovate_mesh.triangles[0][0]]);
  EXPECT_GT(n0.normalized().dot(quads.instances[0].rotation * Eigen::Vector3f::UnitZ()), 0.99f);
  options.phyllotaxis = "fibonacci";
  EXPECT_THROW(GenerateLeaves(TwoBranchTree(), TwoBlobs(), ImageSet(), {}, options, nullptr),
               InputError);
}

}  // namespace
}  // namespace sylva
