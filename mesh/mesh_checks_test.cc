#include "mesh/mesh_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mesh/branch_mesh.h"

namespace sylva {
namespace {

// A closed tube of `sides` sides along +z from z0 to z1, radius r, at x = x0.
void AddTube(double x0, double z0, double z1, double r, int sides, TriangleMesh* mesh) {
  std::vector<TubeRing> rings(2);
  rings[0].center = Eigen::Vector3d(x0, 0, z0);
  rings[1].center = Eigen::Vector3d(x0, 0, z1);
  rings[0].radius = rings[1].radius = r;
  if (mesh->materials.empty())
    mesh->AddMaterial({"bark", Eigen::Vector3f(0.5f, 0.5f, 0.5f), false});
  AppendTube(rings, sides, 0, mesh);
}

double PrismVolume(double r, int sides, double length) {
  return 0.5 * sides * r * r * std::sin(2 * M_PI / sides) * length;
}

TEST(MeshChecksTest, ClosedTubeIsAClosedManifoldWithItsPrismVolume) {
  TriangleMesh mesh;
  AddTube(0, 0, 2, 0.5, 12, &mesh);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_TRUE(check.IsClosedManifold()) << check.BriefReport();
  EXPECT_EQ(check.components, 1);
  EXPECT_EQ(check.self_intersections, 0);
  EXPECT_NEAR(check.volume, PrismVolume(0.5, 12, 2), 1e-5);
  const double side = 2 * 0.5 * std::sin(M_PI / 12);
  const double cap = 0.5 * 12 * 0.25 * std::sin(2 * M_PI / 12);
  EXPECT_NEAR(check.area, 12 * side * 2 + 2 * cap, 1e-5);
}

// Three tubes: one right, one inside out (every triangle reversed), one
// inside out with a hole. CheckMesh counts the inside-out ones; the repair
// turns the closed one and leaves the open one.
TEST(MeshChecksTest, InsideOutComponentsAreCountedAndTheClosedOnesTurned) {
  TriangleMesh mesh;
  AddTube(0, 0, 2, 0.5, 12, &mesh);
  const int first_reversed = mesh.NumTriangles();
  AddTube(3, 0, 2, 0.5, 12, &mesh);
  AddTube(6, 0, 2, 0.5, 12, &mesh);
  for (int t = first_reversed; t < mesh.NumTriangles(); ++t) {
    std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  }
  mesh.triangles.pop_back();  // the open tube loses a cap triangle
  mesh.triangle_materials.pop_back();
  const MeshCheck before = CheckMesh(mesh, "", false);
  EXPECT_EQ(before.components, 3);
  EXPECT_EQ(before.inside_out_components, 2);
  EXPECT_EQ(TurnInsideOutComponents(&mesh), 1);
  const MeshCheck after = CheckMesh(mesh, "", false);
  EXPECT_EQ(after.inside_out_components, 1);
  EXPECT_EQ(after.misoriented_edges, 0);
  // The turned tube's volume went from -V to +V.
  EXPECT_NEAR(after.volume - before.volume, 2 * PrismVolume(0.5, 12, 2), 1e-4);
  EXPECT_EQ(TurnInsideOutComponents(&mesh), 0);
}

TEST(MeshChecksTest, CountsHolesFlipsAndDegenerateTriangles) {
  TriangleMesh mesh;
  AddTube(0, 0, 1, 0.5, 8, &mesh);
  TriangleMesh holed = mesh;
  holed.triangles.pop_back();
  holed.triangle_materials.pop_back();
  MeshCheck check = CheckMesh(holed);
  EXPECT_EQ(check.boundary_edges, 3);
  EXPECT_FALSE(check.IsClosedManifold());

  TriangleMesh flipped = mesh;
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  check = CheckMesh(flipped);
  EXPECT_EQ(check.boundary_edges, 0);
  EXPECT_EQ(check.misoriented_edges, 3);
  EXPECT_FALSE(check.IsClosedManifold());

  TriangleMesh degenerate = mesh;
  degenerate.AddTriangle(0, 0, 1, 0);
  check = CheckMesh(degenerate);
  EXPECT_EQ(check.degenerate_triangles, 1);

  // A third triangle on an existing edge makes it non-manifold.
  TriangleMesh fin = mesh;
  const int v = fin.AddVertex(Eigen::Vector3f(3, 3, 3));
  fin.AddTriangle(mesh.triangles[0][0], mesh.triangles[0][1], v, 0);
  check = CheckMesh(fin);
  EXPECT_EQ(check.nonmanifold_edges, 1);
  EXPECT_EQ(check.boundary_edges, 2);
}

TEST(MeshChecksTest, FindsCrossingTubesAndNotSeparateOnes) {
  TriangleMesh apart;
  AddTube(0, 0, 1, 0.3, 10, &apart);
  AddTube(1, 0, 1, 0.3, 10, &apart);
  MeshCheck check = CheckMesh(apart);
  EXPECT_EQ(check.components, 2);
  EXPECT_EQ(check.self_intersections, 0);
  EXPECT_TRUE(check.IsClosedManifold());
  EXPECT_NEAR(check.volume, 2 * PrismVolume(0.3, 10, 1), 1e-5);

  TriangleMesh crossing;
  AddTube(0, 0, 1, 0.3, 10, &crossing);
  AddTube(0.4, 0, 1, 0.3, 10, &crossing);
  check = CheckMesh(crossing);
  EXPECT_GT(check.self_intersections, 0);
  EXPECT_FALSE(check.IsClosedManifold());
  // Not counted when switched off.
  EXPECT_EQ(CheckMesh(crossing, "", false).self_intersections, -1);
  // An unknown material selects nothing.
  EXPECT_EQ(CheckMesh(crossing, "leaves").triangles, 0);
}

// The whole-mesh search walks the grid's cells and meets each pair in the
// first cell both share; the ordered search (a few pairs wanted) looks each
// triangle's cells up. On a soup of triangles from a hair's width to half
// the soup's size, some sharing vertices, both find the same pairs.
TEST(MeshChecksTest, CellWalkFindsWhatTheOrderedSearchFinds) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  TriangleMesh soup;
  soup.AddMaterial({"bark", Eigen::Vector3f(0.5f, 0.5f, 0.5f), false});
  for (int t = 0; t < 3000; ++t) {
    const float size = 0.002f * std::pow(250.0f, unit(random));  // 0.002 to 0.5
    const Eigen::Vector3f corner(unit(random), unit(random), unit(random));
    int a = soup.AddVertex(corner);
    if (t % 5 == 0 && t > 0) a = static_cast<int>(random() % soup.NumVertices());
    const int b = soup.AddVertex(soup.vertices[a] +
                                 size * Eigen::Vector3f(unit(random), unit(random), unit(random)));
    const int c = soup.AddVertex(soup.vertices[a] +
                                 size * Eigen::Vector3f(unit(random), unit(random), unit(random)));
    soup.AddTriangle(a, b, c, 0);
  }
  const std::vector<std::pair<int, int>> walked = FindSelfIntersections(soup);
  const std::vector<std::pair<int, int>> ordered =
      FindSelfIntersections(soup, "", std::numeric_limits<int64_t>::max());
  EXPECT_GT(walked.size(), 1000u);
  EXPECT_EQ(walked, ordered);
  EXPECT_EQ(CheckMesh(soup).self_intersections, static_cast<int64_t>(walked.size()));
  CrossingTracker tracker;
  EXPECT_EQ(tracker.Find(soup), walked);
}

// The bark's repair rounds mesh the tree again with a few junctions
// changed: the tracker tests only the new triangles and finds the same
// pairs as a whole-mesh search, whatever the triangles' order.
TEST(MeshChecksTest, CrossingTrackerFindsWhatTheWholeSearchFinds) {
  // Twelve tubes in a row, each crossing its neighbours; tube `moved` at x.
  const auto row = [](int moved, double x, bool reversed) {
    TriangleMesh mesh;
    for (int k = 0; k < 12; ++k) {
      const int tube = reversed ? 11 - k : k;
      AddTube(tube == moved ? x : 0.5 * tube, 0, 1, 0.3, 12, &mesh);
    }
    return mesh;
  };
  CrossingTracker tracker;
  const TriangleMesh first = row(-1, 0, false);
  const std::vector<std::pair<int, int>> whole = FindSelfIntersections(first);
  EXPECT_GT(whole.size(), 50u);
  EXPECT_EQ(tracker.Find(first), whole);
  EXPECT_EQ(tracker.last_tested(), first.NumTriangles());
  // One tube moved to cross two others more, listed in another order.
  for (const TriangleMesh& mesh : {row(5, 2.2, true), row(5, 2.6, false), row(-1, 0, false)}) {
    EXPECT_EQ(tracker.Find(mesh), FindSelfIntersections(mesh));
    EXPECT_LE(tracker.last_tested(), mesh.NumTriangles() / 12);
  }
}

}  // namespace
}  // namespace sylva
