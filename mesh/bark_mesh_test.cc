#include "mesh/bark_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/io/qsm_io.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_qsm.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_crossings.h"
#include "mesh/mesh_checks.h"

namespace sylva {
namespace {

// Appends a straight branch of `nodes` edges of length `step` from `from`
// along `direction`, radius falling linearly from r0 to r1. Returns the tip.
int AddBranch(SkeletonGraph* g, int from, const Eigen::Vector3d& direction, int nodes, double step,
              double r0, double r1) {
  int last = from;
  for (int k = 1; k <= nodes; ++k) {
    const double r = r0 + (r1 - r0) * (k - 1) / std::max(1, nodes - 1);
    last = g->AddNode(g->nodes[last].position + step * direction.normalized(), r, last, 0);
  }
  return last;
}

Eigen::Vector3d Tilted(double degrees, double azimuth_degrees) {
  const double a = degrees * M_PI / 180, b = azimuth_degrees * M_PI / 180;
  return Eigen::Vector3d(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a));
}

// A trunk of 3 edges (radius 0.1) whose top node carries `children`
// (tilt from vertical, azimuth, radius), each 4 edges of 0.3.
SkeletonGraph Junction(const std::vector<std::array<double, 3>>& children, double trunk_r = 0.1) {
  SkeletonGraph g;
  const int root = g.AddNode(Eigen::Vector3d::Zero(), trunk_r, -1, 0);
  const int top = AddBranch(&g, root, Eigen::Vector3d::UnitZ(), 3, 0.4, trunk_r, trunk_r);
  for (const auto& c : children) AddBranch(&g, top, Tilted(c[0], c[1]), 4, 0.3, c[2], 0.5 * c[2]);
  g.AssignOrders();
  return g;
}

// Sum over edges of the frustum volumes the tubes sweep (ring radius at a
// node = radius of the edge arriving there; a lateral's first ring = its
// first edge's radius), times the polygon's area factor for `sides` sides.
double FrustumVolume(const SkeletonGraph& g, int sides) {
  double volume = 0.0;
  const std::vector<BranchAxis> axes = g.BranchAxes();
  for (size_t a = 0; a < axes.size(); ++a) {
    for (size_t k = 1; k < axes[a].size(); ++k) {
      const SkeletonNode& p = g.nodes[axes[a][k - 1]];
      const SkeletonNode& c = g.nodes[axes[a][k]];
      const double r0 = (k == 1 && a > 0) ? c.radius : p.radius, r1 = c.radius;
      const double length = (c.position - p.position).norm();
      volume += M_PI * length * (r0 * r0 + r0 * r1 + r1 * r1) / 3;
    }
  }
  return volume * sides * std::sin(2 * M_PI / sides) / (2 * M_PI);
}

BarkMeshOptions FixedSides(int sides) {
  BarkMeshOptions options;
  options.tube.min_sides = options.tube.max_sides = sides;
  return options;
}

// `max_crossing_fraction`: self-intersecting triangle pairs allowed per
// triangle (0 for the hand-made junctions); `max_junction_crossings`: of
// those, pairs at junctions (ClassifyBarkCrossings).
void ExpectWatertight(const SkeletonGraph& g, const BarkMeshOptions& options, double volume_tol,
                      const std::string& what, double max_crossing_fraction = 0.0,
                      int64_t max_junction_crossings = 0) {
  BarkMeshSummary summary;
  std::vector<BarkTriangleOrigin> origins;
  const TriangleMesh mesh = MeshBarkWatertight(g, options, &summary, &origins);
  const MeshCheck check = CheckMesh(mesh);
  const BarkCrossings crossings = ClassifyBarkCrossings(g, mesh, origins);
  EXPECT_EQ(crossings.pairs, check.self_intersections);
  EXPECT_LE(crossings.at_junctions, max_junction_crossings) << crossings.BriefReport();
  SCOPED_TRACE(what + ": " + summary.BriefReport() + " " + check.BriefReport());
  EXPECT_EQ(summary.failed_joints, 0);
  EXPECT_EQ(check.boundary_edges, 0);
  EXPECT_EQ(check.nonmanifold_edges, 0);
  EXPECT_EQ(check.misoriented_edges, 0);
  EXPECT_EQ(check.degenerate_triangles, 0);
  EXPECT_LE(check.self_intersections, max_crossing_fraction * check.triangles);
  EXPECT_EQ(check.components, 1);
  EXPECT_EQ(check.inside_out_components, 0);
  EXPECT_GT(check.volume, 0);
  if (volume_tol > 0) {
    const double reference = FrustumVolume(g, options.tube.max_sides);
    EXPECT_NEAR(check.volume / reference, 1.0, volume_tol);
    std::printf("%s: volume / frustum sum %.4f, %d triangles, %s (%d junctions repaired)\n",
                what.c_str(), check.volume / reference, check.triangles,
                crossings.BriefReport().c_str(), summary.repaired);
  }
}

TEST(BarkMeshTest, HandMadeJunctionsAreClosedManifolds) {
  const BarkMeshOptions options = FixedSides(16);
  ExpectWatertight(Junction({{{30, 0, 0.07}}, {{30, 180, 0.07}}}), options, 0.05, "Y");
  ExpectWatertight(Junction({{{40, 0, 0.06}}, {{40, 120, 0.06}}, {{40, 240, 0.06}}}), options, 0.05,
                   "three children");
  ExpectWatertight(Junction({{{0, 0, 0.09}}, {{90, 0, 0.05}}}), options, 0.05, "90 degrees");
  ExpectWatertight(Junction({{{0, 0, 0.2}}, {{60, 45, 0.005}}}, 0.2), options, 0.05,
                   "thin child on a thick parent");
  ExpectWatertight(Junction({{{3, 0, 0.07}}, {{3, 180, 0.07}}}), options, 0.0, "near-parallel");
  ExpectWatertight(Junction({{{0, 0, 0.08}}, {{2, 90, 0.06}}}), options, 0.0,
                   "near-parallel child and parent");
}

// Closed, one component, outward, volume within 6 % of the frustum sum
// (measured 0.946-0.979: the joints replace the tubes' overlaps, the splines
// cut corners). NOT yet free of self-intersections (measured with 12 sides,
// ClassifyBarkCrossings): most crossing pairs (84-792 per tree of ~100k
// triangles) are where branches of the synthetic skeleton pass through each
// other, 0-90 within one branch (tight bends), and 0-31 at junctions (0 on
// five of the ten trees; joints next to twig clusters). The bounds below
// document that state; they are no goal.
TEST(BarkMeshTest, SyntheticTreesAreClosedManifolds) {
  SyntheticTreeOptions tree;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const SkeletonGraph g = GenerateSyntheticSkeleton(tree, seed);
    ExpectWatertight(g, FixedSides(12), 0.06, "seed " + std::to_string(seed), 0.01, 40);
  }
}

// Laser-scan-like QSM tables of thousands of cylinders (synthetic_qsm.h),
// their kinks made harsher than the defaults (cut points wander by a whole
// radius, radii by 30 %), meshed as mesh-qsm meshes them (connectors inside
// the parent dropped, polygons of the circle's area): no component is inside
// out, the bark holds the cylinders' union within 3 %, and it has the
// components mesh/bark_mesh.h promises: one per part, plus one per lateral
// the summaries count as unattached. Measured (seeds 1, 2): 0.986, 1.011;
// 14 and 17 components (5 parts, 9-12 laterals capped and overlapping their
// parent); before WithoutCrossingRings could drop a capped tube's first
// ring: 4 inside out, 41 laterals overlapping.
TEST(BarkMeshTest, LargeNoisyQsmTablesAreOutwardAndHoldTheirCylinders) {
  SyntheticQsmOptions synth;
  synth.position_noise = 1.0;
  synth.radius_noise = 0.3;
  QsmToSkeletonOptions convert;
  convert.merge_fraction = 0.1;
  convert.merge_inside_parent = true;
  BarkMeshOptions options;
  options.tube.circle_area = true;
  for (uint64_t seed : {1, 2}) {
    const QsmModel qsm = GenerateSyntheticQsm(synth, seed);
    ASSERT_GE(qsm.cylinders.size(), 3000u);
    TriangleMesh bark;
    int parts = 0, unattached = 0;
    for (const QsmSkeleton& part : SkeletonsFromQsm(qsm, convert)) {
      BarkMeshSummary summary;
      bark.Append(MeshBarkWatertight(part.skeleton, options, &summary));
      ++parts;
      unattached += summary.unattached;
      EXPECT_EQ(summary.failed_joints, 0) << seed;
    }
    const MeshCheck check = CheckMesh(bark, "", false);
    const double union_volume = QsmUnionVolume(qsm, 64, 1);
    std::printf("noisy QSM seed %d: %zu cylinders; %s; volume / union %.4f\n",
                static_cast<int>(seed), qsm.cylinders.size(), check.BriefReport().c_str(),
                check.volume / union_volume);
    EXPECT_EQ(check.inside_out_components, 0) << seed;
    EXPECT_EQ(check.boundary_edges + check.nonmanifold_edges + check.misoriented_edges, 0) << seed;
    EXPECT_EQ(parts, 5) << seed;
    EXPECT_GT(unattached, 0) << seed;  // the promise is put to work
    EXPECT_EQ(check.components, parts + unattached) << seed;
    EXPECT_NEAR(check.volume / union_volume, 1.0, 0.03) << seed;
  }
}

TEST(BarkMeshTest, RejectsBadOptionsAndSkeletons) {
  const SkeletonGraph g = Junction({{{30, 0, 0.07}}, {{30, 180, 0.07}}});
  BarkMeshOptions options;
  options.sphere_margin = 0;
  EXPECT_THROW(MeshBarkWatertight(g, options, nullptr), InputError);
  options = BarkMeshOptions();
  options.max_cut_fraction = 1;
  EXPECT_THROW(MeshBarkWatertight(g, options, nullptr), InputError);
  options = BarkMeshOptions();
  options.tube.min_sides = 2;
  EXPECT_THROW(MeshBarkWatertight(g, options, nullptr), InputError);
  SkeletonGraph zero = g;
  for (SkeletonNode& node : zero.nodes) node.radius = 0;
  EXPECT_THROW(MeshBarkWatertight(zero, BarkMeshOptions(), nullptr), InputError);
}

TEST(BarkMeshTest, Deterministic) {
  const SkeletonGraph g = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 3);
  const TriangleMesh a = MeshBarkWatertight(g, BarkMeshOptions(), nullptr);
  const TriangleMesh b = MeshBarkWatertight(g, BarkMeshOptions(), nullptr);
  ASSERT_EQ(a.NumTriangles(), b.NumTriangles());
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
}

}  // namespace
}  // namespace sylva
