#include "mesh/twigs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/util/check.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/branch_mesh.h"
#include "mesh/mesh_checks.h"

namespace sylva {
namespace {

// A trunk to z = 3 with one horizontal branch at z = 2 reaching x = 4: the
// branch is the only terminal branch (the trunk bears it).
SkeletonGraph TrunkAndBranch() {
  SkeletonGraph skeleton;
  const int root = skeleton.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int fork = skeleton.AddNode({0, 0, 2}, 0.15, root, 0);
  skeleton.AddNode({0, 0, 3}, 0.1, fork, 0);
  int node = fork;
  for (int x = 1; x <= 4; ++x) node = skeleton.AddNode({double(x), 0, 2}, 0.06 - 0.01 * x, node, 1);
  return skeleton;
}

// Opacity 0.6 around the branch's inner half (x < 2), 0.2 around its outer half.
DensityGrid BranchDensity() {
  DensityGrid grid(0.1, Eigen::Vector3d::Zero());
  for (int i = 0; i <= 40; ++i)
    for (int j = -5; j <= 5; ++j)
      for (int k = 15; k <= 25; ++k) grid.SetValue({i, j, k}, i < 20 ? 0.6f : 0.2f);
  return grid;
}

std::vector<int> TwigBases(const SkeletonGraph& skeleton, const TwigSummary& summary) {
  std::vector<int> bases;
  for (int i = summary.first_added_node; i < skeleton.NumNodes(); ++i) {
    const SkeletonNode& node = skeleton.nodes[i];
    if (node.order == summary.twig_order &&
        skeleton.nodes[node.parent_idx].order < summary.twig_order) {
      bases.push_back(i);
    }
  }
  return bases;
}

TEST(TwigsTest, TwigsFollowTheDensityOnTerminalBranchesOnly) {
  TwigOptions options;
  options.length = 0.05;
  options.twigs_per_length = 4.0;  // ~ 0.8 per 0.1 of branch at mean density
  TwigSummary summary;
  const SkeletonGraph twigs = GrowTwigs(TrunkAndBranch(), BranchDensity(), options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  twigs.Check();
  EXPECT_EQ(summary.terminal_branches, 1);
  EXPECT_EQ(summary.twig_order, 2);
  const std::vector<int> bases = TwigBases(twigs, summary);
  EXPECT_EQ(static_cast<int>(bases.size()), summary.twigs);
  int inner = 0, outer = 0;
  for (int b : bases) {
    const Eigen::Vector3d& at = twigs.nodes[twigs.nodes[b].parent_idx].position;
    EXPECT_NEAR(at.z(), 2.0, 1e-9);  // on the branch, never on the trunk
    EXPECT_GT(at.x(), 0.0);
    (at.x() < 2.0 ? inner : outer)++;
  }
  // Expected 4 / 0.05 x (1.5, 0.5) x 2 m = 240 and 80 twigs.
  EXPECT_NEAR(inner, 240, 50);
  EXPECT_NEAR(static_cast<double>(inner) / outer, 3.0, 0.8);
}

TEST(TwigsTest, InputNodesKeptTwigsThinnerAndMeshed) {
  const SkeletonGraph input = TrunkAndBranch();
  TwigOptions options;
  options.twigs_per_length = 2.0;
  TwigSummary summary;
  const SkeletonGraph twigs = GrowTwigs(input, BranchDensity(), options, &summary);
  ASSERT_GT(summary.twigs, 5);
  EXPECT_NEAR(summary.twig_length, 0.04 * 3.0, 1e-12);  // length_fraction x height
  for (int i = 0; i < input.NumNodes(); ++i) {
    EXPECT_EQ(twigs.nodes[i].position, input.nodes[i].position);
    EXPECT_EQ(twigs.nodes[i].radius, input.nodes[i].radius);
    EXPECT_EQ(twigs.nodes[i].order, input.nodes[i].order);
  }
  // Pipe model: base radius = branch tip radius (0.02) x 0.25^(1/2).
  for (int b : TwigBases(twigs, summary)) {
    EXPECT_LE(twigs.nodes[b].radius, 0.01 + 1e-12);
    EXPECT_GE(twigs.nodes[b].radius, 0.01 * options.tip_taper - 1e-12);
  }
  // The input's tips are still tips; twigs end in new ones.
  const auto children = twigs.Children();
  for (int tip : input.Tips()) EXPECT_TRUE(children[tip].empty()) << tip;
  const TriangleMesh bare = MeshBranches(input, BranchMeshOptions(), nullptr);
  const TriangleMesh with_twigs = MeshBranches(twigs, BranchMeshOptions(), nullptr);
  EXPECT_GT(with_twigs.NumTriangles(), bare.NumTriangles() + 10 * summary.twigs);
}

// Mean z of twig ends minus their bases, per unit of twig length.
double MeanRise(const SkeletonGraph& skeleton, const TwigSummary& summary) {
  double rise = 0.0;
  int count = 0;
  const auto children = skeleton.Children();
  for (int b : TwigBases(skeleton, summary)) {
    int node = b;
    while (true) {
      int next = -1;
      for (int c : children[node]) {
        if (skeleton.nodes[c].order == summary.twig_order) next = c;
      }
      if (next < 0) break;
      node = next;
    }
    rise += skeleton.nodes[node].position.z() -
            skeleton.nodes[skeleton.nodes[b].parent_idx].position.z();
    ++count;
  }
  return rise / count / summary.twig_length;
}

TEST(TwigsTest, TropismBendsAndStiffnessResists) {
  TwigOptions options;
  options.twigs_per_length = 3.0;
  options.stiffness = 0.0;
  options.tropism = -1.0;
  TwigSummary down, up, stiff;
  const SkeletonGraph drooping = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &down);
  options.tropism = 1.0;
  const SkeletonGraph rising = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &up);
  options.stiffness = 1.0;
  const SkeletonGraph straight = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &stiff);
  EXPECT_LT(MeanRise(drooping, down), -0.3);
  EXPECT_GT(MeanRise(rising, up), 0.3);
  // Stiff twigs keep the branching cone: on average level with a horizontal branch.
  EXPECT_NEAR(MeanRise(straight, stiff), 0.0, 0.15);
}

TEST(TwigsTest, SympodialZigZagsWithStubsMonopodialHasLaterals) {
  TwigOptions options;
  options.twigs_per_length = 1.0;
  options.tropism = 0.0;
  options.pattern = "sympodial";
  options.sympodial_angle_deg = 30.0;
  TwigSummary summary;
  const SkeletonGraph sympodial = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &summary);
  ASSERT_GT(summary.twigs, 3);
  int stubs = 0;
  for (int i = summary.first_added_node; i < sympodial.NumNodes(); ++i) {
    const SkeletonNode& node = sympodial.nodes[i];
    if (node.order == summary.twig_order + 1) ++stubs;
    const SkeletonNode& parent = sympodial.nodes[node.parent_idx];
    if (node.order != summary.twig_order || parent.order != summary.twig_order) continue;
    // Successive units turn by the sympodial angle.
    const SkeletonNode& grand = sympodial.nodes[parent.parent_idx];
    const Eigen::Vector3d a = (parent.position - grand.position).normalized();
    const Eigen::Vector3d b = (node.position - parent.position).normalized();
    EXPECT_NEAR(std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / M_PI, 30.0, 1e-6);
  }
  EXPECT_EQ(stubs, summary.twigs * (options.segments - 1));

  options.pattern = "monopodial";
  const SkeletonGraph monopodial = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &summary);
  int laterals = 0;
  for (int i = summary.first_added_node; i < monopodial.NumNodes(); ++i) {
    const SkeletonNode& node = monopodial.nodes[i];
    const SkeletonNode& parent = monopodial.nodes[node.parent_idx];
    if (node.order == summary.twig_order + 1 && parent.order == summary.twig_order) ++laterals;
  }
  EXPECT_EQ(laterals, summary.twigs * options.laterals);
}

TEST(TwigsTest, DeterministicBySeedAndOptionsChecked) {
  TwigOptions options;
  const SkeletonGraph a = GrowTwigs(TrunkAndBranch(), BranchDensity(), options);
  const SkeletonGraph b = GrowTwigs(TrunkAndBranch(), BranchDensity(), options);
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  for (int i = 0; i < a.NumNodes(); ++i) EXPECT_EQ(a.nodes[i].position, b.nodes[i].position);
  options.seed = 2;
  const SkeletonGraph c = GrowTwigs(TrunkAndBranch(), BranchDensity(), options);
  EXPECT_TRUE(c.NumNodes() != a.NumNodes() || c.nodes.back().position != a.nodes.back().position);
  options.pattern = "weeping";
  try {
    GrowTwigs(TrunkAndBranch(), BranchDensity(), options);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Twigs.pattern");
  }
}

// Nodes that GrowTwigs added as twigs (not the split nodes on the branches).
bool IsTwig(const SkeletonGraph& grown, const TwigSummary& summary, int i) {
  return i >= summary.first_added_node && grown.nodes[i].order >= summary.twig_order;
}

// Sum over the twig axes' edges of the frustum volumes their tubes sweep
// (a twig's first ring has its first edge's radius), times the area factor
// of a polygon of `sides` sides.
double TwigFrustumVolume(const SkeletonGraph& grown, const TwigSummary& summary, int sides) {
  double volume = 0.0;
  for (const BranchAxis& axis : grown.BranchAxes()) {
    for (size_t k = 1; k < axis.size(); ++k) {
      if (!IsTwig(grown, summary, axis[k])) continue;
      const SkeletonNode& p = grown.nodes[axis[k - 1]];
      const SkeletonNode& c = grown.nodes[axis[k]];
      const double r0 = IsTwig(grown, summary, axis[k - 1]) ? p.radius : c.radius, r1 = c.radius;
      volume += M_PI * (c.position - p.position).norm() * (r0 * r0 + r0 * r1 + r1 * r1) / 3;
    }
  }
  return volume * sides * std::sin(2 * M_PI / sides) / (2 * M_PI);
}

double DistanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t =
      ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Twig tips farther than 2 `reach` from every branch's surface (capsules of
// `branches`' edges) that still have a vertex of `mesh` within `reach`, and
// how many tips were that far.
std::pair<int, int> TipsReached(const SkeletonGraph& grown, const TwigSummary& summary,
                                const SkeletonGraph& branches, const TriangleMesh& mesh,
                                double reach) {
  const auto children = grown.Children();
  int far = 0, reached = 0;
  for (int i = summary.first_added_node; i < grown.NumNodes(); ++i) {
    if (!IsTwig(grown, summary, i) || !children[i].empty()) continue;
    const Eigen::Vector3d& tip = grown.nodes[i].position;
    double surface = 1e300;
    for (const SkeletonNode& node : branches.nodes) {
      if (node.parent_idx < 0) continue;
      surface = std::min(
          surface, DistanceToSegment(tip, branches.nodes[node.parent_idx].position, node.position) -
                       node.radius);
    }
    if (surface < 2 * reach) continue;
    ++far;
    for (const Eigen::Vector3f& v : mesh.vertices) {
      if ((v - tip.cast<float>()).norm() <= reach) {
        ++reached;
        break;
      }
    }
  }
  return {reached, far};
}

// Whether `point` is inside the closed `mesh`: crossings of a ray in a
// fixed, generic direction (Moller-Trumbore), counted modulo 2.
bool Inside(const TriangleMesh& mesh, const Eigen::Vector3d& point) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3137, 0.5821, 0.7507).normalized();
  int crossings = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const Eigen::Vector3d e1 = mesh.vertices[t[1]].cast<double>() - a;
    const Eigen::Vector3d e2 = mesh.vertices[t[2]].cast<double>() - a;
    const Eigen::Vector3d p = dir.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = point - a;
    const double u = s.dot(p) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = dir.dot(q) / det;
    if (u < 0 || v < 0 || u + v > 1 || e2.dot(q) / det <= 0) continue;
    ++crossings;
  }
  return crossings % 2 == 1;
}

// Separate twig meshing on a synthetic tree: the bark of RemoveTwigs is one
// closed manifold that reaches no twig tip, the twigs are one closed tube
// per twig axis whose volume is the twig edges' frustum volume.
TEST(TwigsTest, SeparateMeshingGivesClosedBarkAndOneTubePerTwigAxis) {
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 2);
  TwigOptions options;
  options.twigs_per_length = 0.4;
  TwigSummary summary;
  const SkeletonGraph grown = GrowTwigs(skeleton, DensityGrid(), options, &summary);
  SCOPED_TRACE(summary.BriefReport());
  ASSERT_GT(summary.twigs, 50);

  // The branches: every input node (same index and place) plus one split node per twig.
  const SkeletonGraph branches = RemoveTwigs(grown, summary);
  branches.Check();
  EXPECT_EQ(branches.NumNodes(), skeleton.NumNodes() + summary.twigs);
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    EXPECT_EQ(branches.nodes[i].position, skeleton.nodes[i].position);
    EXPECT_EQ(branches.nodes[i].radius, skeleton.nodes[i].radius);
  }
  EXPECT_NEAR(branches.TotalLength(), skeleton.TotalLength(), 1e-9 * skeleton.TotalLength());

  const TriangleMesh bark = MeshBarkWatertight(branches, BarkMeshOptions(), nullptr);
  const MeshCheck bark_check = CheckMesh(bark, "", false);
  EXPECT_EQ(bark_check.boundary_edges, 0) << bark_check.BriefReport();
  EXPECT_EQ(bark_check.nonmanifold_edges, 0) << bark_check.BriefReport();
  EXPECT_EQ(bark_check.misoriented_edges, 0) << bark_check.BriefReport();
  EXPECT_EQ(bark_check.components, 1) << bark_check.BriefReport();
  // No twig in the bark: its vertices stay away from the twig tips (a
  // joined bark caps every tip).
  const double reach = 0.2 * summary.twig_length;
  const auto [bark_reached, far_tips] = TipsReached(grown, summary, branches, bark, reach);
  EXPECT_GT(far_tips, summary.twigs);
  EXPECT_EQ(bark_reached, 0);

  BranchMeshOptions tube;
  tube.min_sides = tube.max_sides = 6;
  TwigTubesSummary tubes_summary;
  const TriangleMesh twigs = MeshTwigTubes(grown, summary, tube, TwigMeshOptions(), &tubes_summary);
  int twig_tips = 0;  // every twig axis ends at one twig tip
  const auto children = grown.Children();
  for (int i = 0; i < grown.NumNodes(); ++i)
    twig_tips += IsTwig(grown, summary, i) && children[i].empty();
  EXPECT_EQ(tubes_summary.tubes, twig_tips);
  EXPECT_EQ(tubes_summary.tubes, summary.twigs * (1 + options.laterals));  // monopodial
  EXPECT_EQ(tubes_summary.triangles, twigs.NumTriangles());
  ASSERT_EQ(twigs.materials.size(), 1u);
  EXPECT_EQ(twigs.materials[0].name, "twigs");
  const MeshCheck twig_check = CheckMesh(twigs, "", false);
  EXPECT_EQ(twig_check.boundary_edges + twig_check.nonmanifold_edges + twig_check.misoriented_edges,
            0)
      << twig_check.BriefReport();
  EXPECT_EQ(twig_check.components, tubes_summary.tubes);
  EXPECT_EQ(TipsReached(grown, summary, branches, twigs, reach).first, far_tips);
  // The twigs stay attached: their bases (the split nodes) are inside the bark.
  int inside = 0;
  for (int i = skeleton.NumNodes(); i < branches.NumNodes(); ++i) {
    inside += Inside(bark, branches.nodes[i].position);
  }
  // Measured 209 of 210: one base sits on an edge leaving a junction, where
  // the bark mesher cuts branches back to their joint (3 cm from the bark).
  EXPECT_GE(inside, 0.98 * summary.twigs);
  // The tubes are MeshBranches' tubes of the twig axes: their volume is what
  // the twigs add to MeshBranches' overlapping tubes, and close to the twig
  // edges' frustums (measured 0.926: the splines of these short, bent axes
  // cut corners, and a tube starts on its parent's axis).
  const double tubes_with = CheckMesh(MeshBranches(grown, tube, nullptr), "", false).volume;
  const double tubes_without = CheckMesh(MeshBranches(branches, tube, nullptr), "", false).volume;
  EXPECT_NEAR(twig_check.volume, tubes_with - tubes_without, 1e-3 * twig_check.volume);
  const double frustums = TwigFrustumVolume(grown, summary, 6);
  EXPECT_GT(twig_check.volume / frustums, 0.88) << twig_check.BriefReport();
  EXPECT_LT(twig_check.volume / frustums, 1.0) << twig_check.BriefReport();
}

TEST(TwigsTest, SympodialTwigTubesAndRemoveTwigsWithoutTwigs) {
  TwigOptions options;
  options.pattern = "sympodial";
  options.twigs_per_length = 1.0;
  TwigSummary summary;
  const SkeletonGraph grown = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &summary);
  ASSERT_GT(summary.twigs, 3);
  TwigTubesSummary tubes;
  const TriangleMesh mesh =
      MeshTwigTubes(grown, summary, BranchMeshOptions(), TwigMeshOptions(), &tubes);
  // Each twig: its zig-zag axis plus one spent-apex stub per later unit.
  EXPECT_EQ(tubes.tubes, summary.twigs * options.segments);
  EXPECT_EQ(CheckMesh(mesh, "", false).components, tubes.tubes);
  SkeletonGraph broken = grown;
  broken.nodes.back().radius = -1;
  try {
    MeshTwigTubes(broken, summary, BranchMeshOptions(), TwigMeshOptions());
    FAIL() << "a negative radius was meshed";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "skeleton");
  }

  // Nothing grown: the skeleton comes back as it was, and no tubes.
  options.twigs_per_length = 0;
  const SkeletonGraph bare = GrowTwigs(TrunkAndBranch(), DensityGrid(), options, &summary);
  EXPECT_EQ(RemoveTwigs(bare, summary).NumNodes(), TrunkAndBranch().NumNodes());
  EXPECT_EQ(
      MeshTwigTubes(bare, summary, BranchMeshOptions(), TwigMeshOptions(), &tubes).NumTriangles(),
      0);
  EXPECT_EQ(tubes.tubes, 0);
}

TEST(TwigsTest, TwigMeshModeFollowsTheOptionAndThreshold) {
  TwigMeshOptions options;
  options.separate_above = 100;
  EXPECT_EQ(options.mode, "auto");
  EXPECT_FALSE(options.Separate(100));
  EXPECT_TRUE(options.Separate(101));
  options.mode = "joined";
  EXPECT_FALSE(options.Separate(1000000));
  options.mode = "separate";
  EXPECT_TRUE(options.Separate(0));
  options.mode = "apart";
  try {
    options.Check();
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Twigs.mesh");
  }
  options.mode = "auto";
  options.separate_above = -1;
  try {
    options.Check();
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Twigs.separate_above");
  }
}

}  // namespace
}  // namespace sylva
