#include "mesh/branch_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "core/util/check.h"
#include "mesh/allometry.h"

namespace sylva {
namespace {

// ---- Mesh metrics ----

// Enclosed volume by the divergence theorem: sum of signed tetrahedra
// (origin, a, b, c); positive for a closed mesh with outward normals.
double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t.x()].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[t.y()].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t.z()].cast<double>();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

double SurfaceArea(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t.x()].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[t.y()].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t.z()].cast<double>();
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

// Closed and consistently oriented: every directed edge appears once and its
// reverse appears once too.
bool IsClosedAndOriented(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> edges;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : edges) {
    if (count != 1) return false;
    const auto reverse = edges.find({edge.second, edge.first});
    if (reverse == edges.end() || reverse->second != 1) return false;
  }
  return true;
}

// Number of connected components of the triangles (by shared vertices).
int NumComponents(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.NumVertices());
  for (int i = 0; i < mesh.NumVertices(); ++i) parent[i] = i;
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    parent[find(t.y())] = find(t.x());
    parent[find(t.z())] = find(t.x());
  }
  int components = 0;
  for (int i = 0; i < mesh.NumVertices(); ++i) components += find(i) == i;
  return components;
}

// Area of a regular n-gon inscribed in a circle of radius r.
double PolygonArea(int n, double r) { return 0.5 * n * r * r * std::sin(2 * M_PI / n); }

// ---- Skeletons ----

// A straight vertical axis of `edges` edges of length `edge`, all radii `radius`.
SkeletonGraph StraightAxis(int edges, double edge, double radius) {
  SkeletonGraph skeleton;
  int parent = -1;
  for (int i = 0; i <= edges; ++i) {
    parent = skeleton.AddNode(Eigen::Vector3d(0.0, 0.0, i * edge), radius, parent, 0);
  }
  return skeleton;
}

// A trunk of 4 edges with two laterals: one at node 2 going +X, one at node 3
// going -Y, each of 3 edges; pipe-model radii from tip counts.
SkeletonGraph BranchedSkeleton() {
  SkeletonGraph skeleton = StraightAxis(4, 1.0, 0.0);
  int parent = 2;
  for (int i = 1; i <= 3; ++i) {
    parent = skeleton.AddNode(Eigen::Vector3d(0.6 * i, 0.0, 2.0 + 0.4 * i), 0.0, parent, 1);
  }
  parent = 3;
  for (int i = 1; i <= 3; ++i) {
    parent = skeleton.AddNode(Eigen::Vector3d(0.0, -0.5 * i, 3.0 + 0.3 * i), 0.0, parent, 1);
  }
  AllometryOptions allometry;
  allometry.trunk_radius = 0.2;
  AssignPipeModelRadii(allometry, &skeleton);
  return skeleton;
}

// ---- Tests ----

TEST(BranchMeshTest, StraightAxisIsAClosedPrismOfTheRightSize) {
  const double radius = 0.2, length = 3.0;
  const SkeletonGraph skeleton = StraightAxis(3, 1.0, radius);
  BranchMeshOptions options;
  options.max_sides = 16;
  BranchMeshSummary summary;
  const TriangleMesh mesh = MeshBranches(skeleton, options, &summary);
  ASSERT_NO_THROW(mesh.Check());
  EXPECT_EQ(summary.axes, 1);
  EXPECT_EQ(summary.rings, 3 * options.rings_per_segment + 1);
  EXPECT_EQ(summary.triangles, mesh.NumTriangles());
  EXPECT_EQ(mesh.NumTriangles(), 2 * 16 * (summary.rings - 1) + 2 * 16);
  EXPECT_TRUE(IsClosedAndOriented(mesh));
  // The polygonal prism exactly (float vertices), and the cylinder within
  // the polygon's deficit (1 - sin(2 pi / n) n / (2 pi) = 2.6% for n = 16).
  const double prism_volume = PolygonArea(16, radius) * length;
  const double prism_area =
      16 * 2 * radius * std::sin(M_PI / 16) * length + 2 * PolygonArea(16, radius);
  EXPECT_NEAR(SignedVolume(mesh), prism_volume, 1e-6 * prism_volume);
  EXPECT_NEAR(SurfaceArea(mesh), prism_area, 1e-6 * prism_area);
  const double cylinder_volume = M_PI * radius * radius * length;
  const double deficit = 1 - std::sin(2 * M_PI / 16) * 16 / (2 * M_PI);
  EXPECT_NEAR(SignedVolume(mesh), cylinder_volume, 1.01 * deficit * cylinder_volume);
  EXPECT_EQ(mesh.materials.size(), 1u);
  EXPECT_EQ(mesh.materials[0].name, "bark");
}

// circle_area: the polygons get the circle's area, so the prism holds the
// cylinder's volume whatever its sides (4: the square's vertices 1.25 r out).
TEST(BranchMeshTest, CircleAreaRingsHoldTheCylindersVolume) {
  const double radius = 0.2, length = 3.0;
  const SkeletonGraph skeleton = StraightAxis(3, 1.0, radius);
  for (int sides : {4, 6, 16}) {
    BranchMeshOptions options;
    options.min_sides = options.max_sides = sides;
    options.circle_area = true;
    const TriangleMesh mesh = MeshBranches(skeleton, options, nullptr);
    EXPECT_TRUE(IsClosedAndOriented(mesh));
    const double cylinder_volume = M_PI * radius * radius * length;
    EXPECT_NEAR(SignedVolume(mesh), cylinder_volume, 1e-6 * cylinder_volume) << sides;
    EXPECT_NEAR(mesh.vertices[0].cast<double>().head<2>().norm(),
                radius * PolygonAreaRadiusScale(sides), 1e-6)
        << sides;
  }
  EXPECT_NEAR(PolygonAreaRadiusScale(4), std::sqrt(M_PI / 2), 1e-12);
}

TEST(BranchMeshTest, EveryVertexOfAStraightTubeIsAtTheRadius) {
  const SkeletonGraph skeleton = StraightAxis(5, 0.7, 0.35);
  const TriangleMesh mesh = MeshBranches(skeleton, BranchMeshOptions(), nullptr);
  int on_axis = 0;
  for (const Eigen::Vector3f& v : mesh.vertices) {
    const double distance = Eigen::Vector2d(v.x(), v.y()).norm();
    if (distance < 1e-6) {
      ++on_axis;  // the two cap centres
      continue;
    }
    EXPECT_NEAR(distance, 0.35, 1e-6);
    EXPECT_GE(v.z(), -1e-6);
    EXPECT_LE(v.z(), 3.5 + 1e-6);
  }
  EXPECT_EQ(on_axis, 2);
}

TEST(BranchMeshTest, TrianglesFaceOutwards) {
  const SkeletonGraph skeleton = StraightAxis(2, 1.0, 0.5);
  const TriangleMesh mesh = MeshBranches(skeleton, BranchMeshOptions(), nullptr);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t.x()].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[t.y()].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t.z()].cast<double>();
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    const Eigen::Vector3d centroid = (a + b + c) / 3;
    // Away from the axis point at the centroid's height (caps: along +-Z).
    const Eigen::Vector3d outward =
        centroid - Eigen::Vector3d(0, 0, std::clamp(centroid.z(), 0.25, 1.75));
    EXPECT_GT(normal.dot(outward), 0.0);
  }
  EXPECT_GT(SignedVolume(mesh), 0.0);
}

TEST(BranchMeshTest, TaperedAxisHasTheFrustumVolume) {
  // Radii 0.3 at the base, then 0.3, 0.2, 0.1 at the next nodes: linear
  // taper per edge, so each edge is a polygonal frustum.
  SkeletonGraph skeleton = StraightAxis(3, 1.0, 0.3);
  skeleton.nodes[2].radius = 0.2;
  skeleton.nodes[3].radius = 0.1;
  BranchMeshOptions options;
  options.max_sides = 12;
  const TriangleMesh mesh = MeshBranches(skeleton, options, nullptr);
  auto frustum = [](double r0, double r1) {
    const double a0 = PolygonArea(12, r0), a1 = PolygonArea(12, r1);
    return (a0 + a1 + std::sqrt(a0 * a1)) / 3.0;
  };
  const double expected = frustum(0.3, 0.3) + frustum(0.3, 0.2) + frustum(0.2, 0.1);
  EXPECT_NEAR(SignedVolume(mesh), expected, 1e-6 * expected);
  EXPECT_TRUE(IsClosedAndOriented(mesh));
}

TEST(BranchMeshTest, CurvedAxisFollowsItsSplineAtTheRadius) {
  // A quarter circle of radius 2 in the XZ plane, 12 edges; the tube volume
  // is close to pi r^2 times the arc length (Pappus). The spline cuts inside
  // the arc by at most |P_{k-1} - 2 P_k + P_{k+1}| / 6 = chord^2 / (6 R).
  SkeletonGraph skeleton;
  int parent = -1;
  for (int i = 0; i <= 12; ++i) {
    const double angle = 0.5 * M_PI * i / 12;
    parent = skeleton.AddNode(Eigen::Vector3d(2 - 2 * std::cos(angle), 0, 2 * std::sin(angle)), 0.1,
                              parent, 0);
  }
  BranchMeshOptions options;
  options.max_sides = 64;
  options.rings_per_segment = 8;
  const std::vector<BranchTube> tubes = PlanBranchTubes(skeleton, options);
  ASSERT_EQ(tubes.size(), 1u);
  const std::vector<TubeRing> rings = SampleTubeRings(tubes[0]);
  const double chord = 2 * 2 * std::sin(M_PI / 48);
  for (const TubeRing& ring : rings) {
    const double from_centre = (ring.center - Eigen::Vector3d(2, 0, 0)).norm();
    EXPECT_LE(from_centre, 2.0 + 1e-12);
    EXPECT_GE(from_centre, 2.0 - 1.05 * chord * chord / (6 * 2.0));
    EXPECT_NEAR(ring.frame.normal.dot(ring.frame.tangent), 0.0, 1e-12);
  }
  const TriangleMesh mesh = MeshBranches(skeleton, options, nullptr);
  EXPECT_TRUE(IsClosedAndOriented(mesh));
  const double expected = M_PI * 0.01 * M_PI;  // pi r^2 * (pi / 2 * 2)
  EXPECT_NEAR(SignedVolume(mesh), expected, 0.01 * expected);
}

TEST(BranchMeshTest, FirstRingsAreTheWholeTubesFirstRings) {
  // Straight for six edges, then bending: the frames' initial normal comes
  // from the bend, beyond the first rings, and must be the same.
  SkeletonGraph skeleton;
  int parent = -1;
  for (int i = 0; i <= 10; ++i) {
    const double bend = i <= 6 ? 0.0 : 0.3 * (i - 6) * (i - 6);
    parent = skeleton.AddNode(Eigen::Vector3d(bend, 0.1 * bend, i), 0.2, parent, 0);
  }
  BranchMeshOptions options;
  options.rings_per_segment = 3;
  const std::vector<BranchTube> tubes = PlanBranchTubes(skeleton, options);
  ASSERT_EQ(tubes.size(), 1u);
  const std::vector<TubeRing> all = SampleTubeRings(tubes[0]);
  ASSERT_EQ(static_cast<int>(all.size()), tubes[0].NumRings());
  for (int count : {1, 2, 6, 17, 1000}) {
    const std::vector<TubeRing> first = SampleTubeRings(tubes[0], count);
    ASSERT_EQ(first.size(), std::min(all.size(), static_cast<size_t>(count)));
    for (size_t i = 0; i < first.size(); ++i) {
      EXPECT_EQ(first[i].center, all[i].center) << "ring " << i << " of " << count;
      EXPECT_EQ(first[i].frame.normal, all[i].frame.normal);
      EXPECT_EQ(first[i].frame.binormal, all[i].frame.binormal);
      EXPECT_EQ(first[i].radius, all[i].radius);
    }
  }
}

TEST(BranchMeshTest, BranchedSkeletonGivesOneClosedTubePerAxis) {
  const SkeletonGraph skeleton = BranchedSkeleton();
  BranchMeshSummary summary;
  const TriangleMesh mesh = MeshBranches(skeleton, BranchMeshOptions(), &summary);
  EXPECT_EQ(summary.axes, 3);
  EXPECT_EQ(summary.skipped_axes, 0);
  EXPECT_EQ(NumComponents(mesh), 3);
  EXPECT_TRUE(IsClosedAndOriented(mesh));
  EXPECT_EQ(summary.radius_source, "allometric prior");
  EXPECT_NE(summary.BriefReport().find("allometric prior"), std::string::npos);
  // Laterals start at their junction with their own first radius, and get
  // fewer sides than the trunk.
  const std::vector<BranchTube> tubes = PlanBranchTubes(skeleton, BranchMeshOptions());
  ASSERT_EQ(tubes.size(), 3u);
  EXPECT_EQ(tubes[1].control_points.front(), skeleton.nodes[2].position);
  EXPECT_EQ(tubes[1].radii.front(), skeleton.nodes[5].radius);
  EXPECT_LT(tubes[1].radii.front(), skeleton.nodes[2].radius);
  EXPECT_EQ(tubes[0].sides, BranchMeshOptions().max_sides);
  EXPECT_LT(tubes[1].sides, tubes[0].sides);
  int64_t triangles = 0;
  for (const BranchTube& tube : tubes) triangles += tube.NumTriangles();
  EXPECT_EQ(triangles, mesh.NumTriangles());
}

TEST(BranchMeshTest, RingsPerUnitLengthRefinesLongEdges) {
  SkeletonGraph skeleton = StraightAxis(2, 1.0, 0.1);
  skeleton.nodes[2].position.z() = 11.0;  // edges of 1 and 10
  BranchMeshOptions options;
  options.rings_per_segment = 2;
  options.rings_per_unit_length = 1.5;
  const std::vector<BranchTube> tubes = PlanBranchTubes(skeleton, options);
  ASSERT_EQ(tubes.size(), 1u);
  EXPECT_EQ(tubes[0].rings_per_segment, (std::vector<int>{2, 15}));
}

TEST(BranchMeshTest, CoincidentNodesAreMergedAndEmptyAxesSkipped) {
  SkeletonGraph skeleton = StraightAxis(3, 1.0, 0.1);
  skeleton.nodes[2].position = skeleton.nodes[1].position;   // a zero-length edge
  skeleton.AddNode(skeleton.nodes[2].position, 0.05, 2, 1);  // a lateral of zero length
  BranchMeshSummary summary;
  const TriangleMesh mesh = MeshBranches(skeleton, BranchMeshOptions(), &summary);
  EXPECT_EQ(summary.axes, 1);
  EXPECT_EQ(summary.skipped_axes, 1);
  EXPECT_TRUE(IsClosedAndOriented(mesh));
  for (const Eigen::Vector3f& v : mesh.vertices) EXPECT_TRUE(v.allFinite());
}

TEST(BranchMeshTest, Deterministic) {
  const SkeletonGraph skeleton = BranchedSkeleton();
  const TriangleMesh a = MeshBranches(skeleton, BranchMeshOptions(), nullptr);
  const TriangleMesh b = MeshBranches(skeleton, BranchMeshOptions(), nullptr);
  ASSERT_EQ(a.NumVertices(), b.NumVertices());
  for (int i = 0; i < a.NumVertices(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(BranchMeshTest, AbsurdInputsAreInputErrors) {
  SkeletonGraph skeleton = StraightAxis(2, 1.0, 0.1);
  skeleton.nodes[1].radius = -0.1;
  EXPECT_THROW(MeshBranches(skeleton, BranchMeshOptions(), nullptr), InputError);
  skeleton = StraightAxis(2, 1.0, 0.1);
  skeleton.nodes[1].position.x() = std::nan("");
  EXPECT_THROW(MeshBranches(skeleton, BranchMeshOptions(), nullptr), InputError);
  skeleton = StraightAxis(2, 1.0, 0.0);
  try {
    MeshBranches(skeleton, BranchMeshOptions(), nullptr);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "skeleton");
    EXPECT_NE(error.message().find("radii"), std::string::npos);
  }
  skeleton = StraightAxis(2, 1.0, 0.1);
  BranchMeshOptions options;
  options.min_sides = 2;
  EXPECT_THROW(MeshBranches(skeleton, options, nullptr), InputError);
  options = BranchMeshOptions();
  options.rings_per_segment = 0;
  EXPECT_THROW(MeshBranches(skeleton, options, nullptr), InputError);
  options = BranchMeshOptions();
  options.rings_per_unit_length = -1;
  EXPECT_THROW(MeshBranches(skeleton, options, nullptr), InputError);
}

TEST(BranchMeshTest, TinySkeletonsGiveEmptyMeshes) {
  SkeletonGraph skeleton;
  EXPECT_EQ(MeshBranches(skeleton, BranchMeshOptions(), nullptr).NumTriangles(), 0);
  skeleton.AddNode(Eigen::Vector3d::Zero(), 0.1, -1, 0);
  EXPECT_EQ(MeshBranches(skeleton, BranchMeshOptions(), nullptr).NumTriangles(), 0);
}

}  // namespace
}  // namespace sylva
