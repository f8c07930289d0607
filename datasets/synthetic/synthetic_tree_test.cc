#include "datasets/synthetic/synthetic_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;

void ExpectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.triangle_materials, b.triangle_materials);
}

TEST(SyntheticTreeTest, SameSeedSameTreeOtherSeedOtherTree) {
  const SyntheticTreeOptions options;
  const SyntheticTree a = GenerateSyntheticTree(options, 7);
  const SyntheticTree b = GenerateSyntheticTree(options, 7);
  ExpectSameMesh(a.mesh, b.mesh);
  ASSERT_EQ(a.skeleton.NumNodes(), b.skeleton.NumNodes());
  for (int i = 0; i < a.skeleton.NumNodes(); ++i) {
    EXPECT_EQ(a.skeleton.nodes[i].position, b.skeleton.nodes[i].position);
    EXPECT_EQ(a.skeleton.nodes[i].radius, b.skeleton.nodes[i].radius);
    EXPECT_EQ(a.skeleton.nodes[i].parent_idx, b.skeleton.nodes[i].parent_idx);
  }
  const SyntheticTree c = GenerateSyntheticTree(options, 8);
  EXPECT_TRUE(c.mesh.vertices != a.mesh.vertices);
  // Different, but similar: same structure parameters give similar sizes.
  EXPECT_NEAR(c.skeleton.TotalLength(), a.skeleton.TotalLength(), 0.3 * a.skeleton.TotalLength());
  EXPECT_GT(std::abs(c.skeleton.TotalLength() - a.skeleton.TotalLength()), 1e-6);
}

TEST(SyntheticTreeTest, SkeletonIsValidWithPipeModelRadii) {
  const SyntheticTreeOptions options;
  const SyntheticTree tree = GenerateSyntheticTree(options, 1);
  const SkeletonGraph& skeleton = tree.skeleton;
  EXPECT_NO_THROW(skeleton.Check());
  EXPECT_EQ(skeleton.radius_source, "ground truth");
  const int root = skeleton.RootIdx();
  EXPECT_EQ(skeleton.nodes[root].position, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(skeleton.nodes[root].radius, options.trunk_base_radius);
  int max_order = 0;
  for (const SkeletonNode& node : skeleton.nodes) {
    max_order = std::max(max_order, node.order);
    EXPECT_GE(node.radius, options.min_radius);
    if (node.parent_idx < 0) continue;
    const SkeletonNode& parent = skeleton.nodes[node.parent_idx];
    EXPECT_LE(node.radius, parent.radius);
    EXPECT_TRUE(node.order == parent.order || node.order == parent.order + 1);
    EXPECT_LE((node.position - parent.position).norm(), options.max_segment_length + 1e-9);
  }
  EXPECT_EQ(max_order, 3);
}

TEST(SyntheticTreeTest, BranchesLeaveTheirParentsAt30To60Degrees) {
  const SyntheticTree tree = GenerateSyntheticTree(SyntheticTreeOptions(), 3);
  const SkeletonGraph& skeleton = tree.skeleton;
  double sum = 0;
  int count = 0;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const SkeletonNode& parent = skeleton.nodes[node.parent_idx];
    if (parent.order == node.order || parent.parent_idx < 0) continue;
    // The child's first edge against the parent's edge into the branching node;
    // the first edge is already bent by one step of wobble and tropism.
    const Eigen::Vector3d child_dir = (node.position - parent.position).normalized();
    const Eigen::Vector3d parent_dir =
        (parent.position - skeleton.nodes[parent.parent_idx].position).normalized();
    const double angle = std::acos(std::clamp(child_dir.dot(parent_dir), -1.0, 1.0)) / kDegree;
    EXPECT_GT(angle, 15.0);
    EXPECT_LT(angle, 75.0);
    sum += angle;
    ++count;
  }
  EXPECT_GT(count, 300);
  EXPECT_NEAR(sum / count, 45.0, 5.0);
}

TEST(SyntheticTreeTest, SizeAndLeavesAreInTheDocumentedRange) {
  const SyntheticTreeOptions options;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    const SyntheticTree tree = GenerateSyntheticTree(options, seed);
    EXPECT_NO_THROW(tree.mesh.Check());
    const Box3d bounds = tree.mesh.Bounds();
    EXPECT_GT(bounds.max().z(), 5.5);
    EXPECT_LT(bounds.max().z(), 7.5);
    EXPECT_GT(bounds.min().z(), -1e-6);  // flat base at z = 0
    const double width = std::max(bounds.sizes().x(), bounds.sizes().y());
    EXPECT_GT(width, 4.0);
    EXPECT_LT(width, 8.0);
    EXPECT_GT(tree.num_leaves, 20000);
    EXPECT_LE(tree.num_leaves, 50000);
    // One cluster per tip; triangles: 4 per tube side, 2 per leaf.
    int tips = 0;
    for (const auto& children : tree.skeleton.Children()) tips += children.empty() ? 1 : 0;
    EXPECT_EQ(tree.num_clusters, tips);
    // Each cluster's ellipsoid holds its leaves' centres (4 vertices per
    // leaf, after the bark's; the leaves of cluster k come k-th).
    ASSERT_EQ(static_cast<int>(tree.clusters.size()), tree.num_clusters);
    const int first_leaf_vertex = tree.mesh.NumVertices() - 4 * tree.num_leaves;
    for (int leaf = 0; leaf < tree.num_leaves; ++leaf) {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) {
        centre += tree.mesh.vertices[first_leaf_vertex + 4 * leaf + k].cast<double>() / 4.0;
      }
      const SyntheticLeafCluster& cluster = tree.clusters[leaf / options.leaves_per_cluster];
      // float vertices: allow 1e-5 of the cluster's size
      SyntheticLeafCluster grown = cluster;
      grown.along += 1e-5;
      grown.across += 1e-5;
      ASSERT_TRUE(grown.Contains(centre)) << "leaf " << leaf;
    }
    // Contains() and Volume() agree: Monte Carlo over the enclosing cube.
    const SyntheticLeafCluster& cluster = tree.clusters.front();
    const double half = std::max(cluster.along, cluster.across);
    RandomEngine random(seed);
    int inside = 0;
    const int samples = 200000;
    for (int i = 0; i < samples; ++i) {
      const Eigen::Vector3d offset(random.Uniform(-half, half), random.Uniform(-half, half),
                                   random.Uniform(-half, half));
      inside += cluster.Contains(cluster.centre + offset) ? 1 : 0;
    }
    EXPECT_NEAR(std::pow(2 * half, 3) * inside / samples, cluster.Volume(),
                0.02 * cluster.Volume());
    ASSERT_EQ(tree.mesh.materials.size(), 2u);
    EXPECT_EQ(tree.mesh.materials[0].name, "bark");
    EXPECT_EQ(tree.mesh.materials[1].name, "leaves");
    EXPECT_TRUE(tree.mesh.materials[1].double_sided);
    int leaf_triangles = 0;
    for (int m : tree.mesh.triangle_materials) leaf_triangles += m == 1 ? 1 : 0;
    EXPECT_EQ(leaf_triangles, 2 * tree.num_leaves);
  }
}

TEST(SyntheticTreeTest, LeafClustersUnionVolumeCountsOverlapsOnce) {
  SyntheticLeafCluster a;
  a.along = 0.6;
  a.across = 0.4;
  SyntheticLeafCluster far = a;
  far.centre = Eigen::Vector3d(5, 0, 0);
  far.axis = Eigen::Vector3d(1, 0, 0);
  // Disjoint: the sum; the same twice: one; one inside another: the outer.
  EXPECT_NEAR(LeafClustersUnionVolume({a, far}, 20000, 1), a.Volume() + far.Volume(), 1e-12);
  EXPECT_NEAR(LeafClustersUnionVolume({a, a}, 20000, 1), a.Volume(), 1e-12);
  SyntheticLeafCluster inner = a;
  inner.along = inner.across = 0.2;
  EXPECT_NEAR(LeafClustersUnionVolume({a, inner}, 20000, 1), a.Volume(), 1e-12);
  // Two spheres of radius 1 whose centres are 1 apart: 2 x 4/3 pi - the lens
  // (5/12 pi), within Monte Carlo error (about 0.5 %).
  SyntheticLeafCluster left, right;
  left.along = left.across = right.along = right.across = 1.0;
  right.centre = Eigen::Vector3d(0.6, 0.8, 0);
  const double exact = 8.0 / 3.0 * M_PI - 5.0 / 12.0 * M_PI;
  EXPECT_NEAR(LeafClustersUnionVolume({left, right}, 20000, 1), exact, 0.02 * exact);
}

TEST(SyntheticTreeTest, OptionsAreChecked) {
  SyntheticTreeOptions options;
  EXPECT_NO_THROW(options.Check());
  options.trunk_length = -1;
  EXPECT_THROW(GenerateSyntheticTree(options, 1), InputError);
  options = SyntheticTreeOptions();
  options.crown_top = options.crown_base;
  EXPECT_THROW(options.Check(), InputError);
  options = SyntheticTreeOptions();
  options.leaf_length_max = 0.5 * options.leaf_length_min;
  try {
    options.Check();
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "SyntheticTreeOptions.leaf_length_max");
  }
}

TEST(SyntheticTreeTest, TubesAreClosedAndScaleTheirSides) {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0.2, -1, 0);
  skeleton.AddNode({0, 0, 1}, 0.001, root, 0);
  SyntheticTreeOptions options;
  TriangleMesh mesh;
  const int material = mesh.AddMaterial({"bark", options.bark_color, false});
  AddBranchTubes(skeleton, options, material, &mesh);
  const int sides = options.tube_max_sides;  // 2 pi 0.2 / 0.03 > 24
  EXPECT_EQ(mesh.NumTriangles(), 4 * sides);
  // Closed: every edge is shared by exactly two triangles, consistently oriented.
  std::map<std::pair<int, int>, int> directed_edges;
  for (const Eigen::Vector3i& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed_edges[{tri[k], tri[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed_edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed_edges.count({edge.second, edge.first}), 1u);
  }
  // Outward orientation: the signed volume is positive (a frustum).
  double volume = 0;
  for (const Eigen::Vector3i& tri : mesh.triangles) {
    volume += mesh.vertices[tri.x()].cast<double>().dot(mesh.vertices[tri.y()].cast<double>().cross(
                  mesh.vertices[tri.z()].cast<double>())) /
              6.0;
  }
  EXPECT_GT(volume, 0.0);
}

}  // namespace
}  // namespace sylva
