#include "simulate/attractor_field.h"

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/util/check.h"
#include "simulate/particle_flow.h"

namespace sylva {
namespace {

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
}

double AngleDeg2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return AngleDeg(Eigen::Vector3d(a.x(), a.y(), 0), Eigen::Vector3d(b.x(), b.y(), 0));
}

// A vertical line in a 100 x 100 image from a tip at (50, 10) down to the
// root at (50, 90).
AttractorGraph2D VerticalLine() {
  AttractorGraph2D graph;
  graph.width = graph.height = 100;
  graph.root = graph.AddNode({50, 90}, -1);
  graph.AddNode({50, 10}, graph.root);
  return graph;
}

// The linear-blend field at p from the closest point over every segment of
// `graph` (no buckets), with the falloff in pixels; `distance` gets p's
// distance to the graph.
Eigen::Vector2d ExactField(const AttractorGraph2D& graph, const Eigen::Vector2d& p,
                           double falloff_px, double* distance = nullptr) {
  double best = 1e9;
  Eigen::Vector2d closest = Eigen::Vector2d::Zero(), tangent = Eigen::Vector2d::Zero();
  for (const auto& [a, b] : graph.Segments()) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const Eigen::Vector2d q = a + t * (b - a);
    if ((q - p).norm() < best) best = (q - p).norm(), closest = q, tangent = (b - a).normalized();
  }
  if (distance != nullptr) *distance = best;
  const double h = std::min(best / falloff_px, 1.0);
  return h * (closest - p) / best + (1 - h) * tangent;
}

TEST(DirectionField2D, LinearBlendPointsAtTheGraphFarAndAlongItNear) {
  AttractorFieldOptions options;  // linear
  options.falloff = 0.1;          // 10 px
  const DirectionField2D field(VerticalLine(), options);
  EXPECT_EQ(field.cols(), 100);
  EXPECT_EQ(field.rows(), 100);
  // Far (d = 40 > falloff): straight at the closest point.
  EXPECT_LT((field.Evaluate({10, 50}) - Eigen::Vector2d(1, 0)).norm(), 1e-12);
  EXPECT_LT((field.Evaluate({95, 30}) - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
  // Beyond the tip: at the tip.
  EXPECT_LT(AngleDeg2(field.Evaluate({50, -30}), {0, 1}), 1e-9);
  // On the graph: its tangent, down the tree.
  EXPECT_LT((field.Evaluate({50, 50}) - Eigen::Vector2d(0, 1)).norm(), 1e-12);
  // Half the falloff away: half and half.
  EXPECT_LT((field.Evaluate({45, 50}) - Eigen::Vector2d(0.5, 0.5)).norm(), 1e-12);
  // The grid interpolates the exact field (linear in x across the band).
  EXPECT_LT((field.At({45, 50}) - field.Evaluate({45, 50})).norm(), 1e-6);
  EXPECT_LT((field.At({12.3, 61.7}) - Eigen::Vector2d(1, 0)).norm(), 1e-6);
}

TEST(DirectionField2D, ConstantBlendGivesAFixedApproachAngle) {
  AttractorFieldOptions options;
  options.blend = "constant";
  for (double h0 : {0.25, 0.5, 0.75}) {
    options.constant_h = h0;
    const DirectionField2D field(VerticalLine(), options);
    const double expected = std::atan2(h0, 1 - h0) * 180 / M_PI;
    for (double x : {2.0, 20.0, 44.0, 49.5, 55.0, 80.0}) {
      const Eigen::Vector2d f = field.Evaluate({x, 40});
      EXPECT_NEAR(AngleDeg2(f, {0, 1}), expected, 1e-9) << "h0 " << h0 << " x " << x;
      EXPECT_GT(f.x() * (50 - x), 0) << "heads towards the graph";
    }
  }
}

TEST(DirectionField2D, ClosestSegmentOfABranchingGraph) {
  // A Y: trunk (50, 90)-(50, 50), arms to (20, 10) and (80, 10); compare the
  // bucketed search with the exact closest point over all segments.
  AttractorGraph2D graph;
  graph.width = 100;
  graph.height = 120;
  graph.root = graph.AddNode({50, 90}, -1);
  const int fork = graph.AddNode({50, 50}, graph.root);
  graph.AddNode({20, 10}, graph.AddNode({35, 30}, fork));
  graph.AddNode({80, 10}, fork);
  AttractorFieldOptions options;
  options.falloff = 0.2;
  const DirectionField2D field(graph, options);
  EXPECT_EQ(field.rows(), 100);
  EXPECT_EQ(field.cols(), 84);
  for (int y = -10; y <= 130; y += 7) {
    for (int x = -10; x <= 110; x += 7) {
      const Eigen::Vector2d p(x + 0.3, y + 0.6);
      EXPECT_LT((field.Evaluate(p) - ExactField(graph, p, 24.0)).norm(), 1e-9) << p.transpose();
    }
  }
}

TEST(DirectionField2D, ClosestSegmentFarFromAClusteredGraph) {
  // 64 short segments crowded in one corner of a large image: most buckets
  // are empty, and the search starts at the first ring that holds a segment.
  // Every point's closest segment must still be the exact one.
  AttractorGraph2D graph;
  graph.width = 400;
  graph.height = 300;
  graph.root = graph.AddNode({40, 60}, -1);
  int parent = graph.root;
  for (int k = 1; k <= 64; ++k) {
    const double angle = 0.7 * k;
    parent = graph.AddNode(
        {40 + 25 * std::cos(angle) * (k % 5) / 4.0, 60 + 25 * std::sin(angle) * (k % 7) / 6.0},
        k % 3 == 0 ? graph.root : parent);
  }
  AttractorFieldOptions options;
  options.falloff = 0.05;
  const DirectionField2D field(graph, options);
  const double falloff_px = 0.05 * 400;
  int far = 0;
  for (int y = -20; y <= 320; y += 11) {
    for (int x = -20; x <= 420; x += 13) {
      const Eigen::Vector2d p(x + 0.25, y + 0.5);
      double distance = 0;
      const Eigen::Vector2d expected = ExactField(graph, p, falloff_px, &distance);
      far += distance > 100 ? 1 : 0;
      EXPECT_LT((field.Evaluate(p) - expected).norm(), 1e-9) << p.transpose();
    }
  }
  EXPECT_GT(far, 500);  // most points are many empty buckets away
}

// Two orthographic views at right angles: from +X and from +Y, 200 x 200
// pixels, 50 pixels per unit, the origin in the image centre.
ImageSet TwoOrthographicViews() {
  ImageSet set;
  set.cameras[1] = Camera::Orthographic(200, 200, 50);
  Eigen::Matrix3d from_x, from_y;
  from_x << 0, 1, 0, 0, 0, -1, -1, 0, 0;  // rows: x right, y down, z forward
  from_y << -1, 0, 0, 0, 0, -1, 0, -1, 0;
  set.views.push_back({1, "x.png", 1, Rigid3d(Eigen::Quaterniond(from_x), {0, 0, 5})});
  set.views.push_back({2, "y.png", 1, Rigid3d(Eigen::Quaterniond(from_y), {0, 0, 5})});
  return set;
}

// The projection of the 3D segment top -> bottom into a view, as a graph.
AttractorGraph2D ProjectedSegment(const ImageSet& set, int view, const Eigen::Vector3d& top,
                                  const Eigen::Vector3d& bottom) {
  AttractorGraph2D graph;
  graph.width = set.CameraOf(view).width();
  graph.height = set.CameraOf(view).height();
  Eigen::Vector2d a, b;
  EXPECT_TRUE(set.Project(view, top, &a));
  EXPECT_TRUE(set.Project(view, bottom, &b));
  graph.root = graph.AddNode(b, -1);
  graph.AddNode(a, graph.root);
  return graph;
}

TEST(AttractorDirectionField, LiftingTwoOrthographicViewsRecoversA3dDirection) {
  const ImageSet set = TwoOrthographicViews();
  const Eigen::Vector3d x(0.1, -0.1, 0.2);
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  AttractorFieldOptions options;
  options.resolution = 200;  // one cell per pixel
  options.resolution_3d = 48;
  options.falloff = 0.1;
  // A direction seen equally in both views: the mean of the lifted
  // directions recovers it (the thesis' average).
  const Eigen::Vector3d symmetric = Eigen::Vector3d(0.4, 0.4, -0.8).normalized();
  // A general direction: only the intersection of the views' planes does.
  const Eigen::Vector3d general = Eigen::Vector3d(0.3, 0.6, -0.75).normalized();
  for (const std::string combine : {"average", "intersect"}) {
    options.combine = combine;
    for (const Eigen::Vector3d& u : {symmetric, general}) {
      if (combine == "average" && u == general) continue;
      std::vector<AttractorGraph2D> graphs;
      for (int v = 0; v < 2; ++v)
        graphs.push_back(ProjectedSegment(set, v, x - 0.6 * u, x + 0.6 * u));
      const AttractorDirectionField field(set, graphs, bounds, options);
      EXPECT_EQ(field.NumViewsWithGraphs(), 2);
      EXPECT_LT(AngleDeg(field.Lifted(x), u), 0.5) << combine << " " << u.transpose();
      EXPECT_LT(AngleDeg(field.Direction(x), u), 1.0) << combine << " " << u.transpose();
      // Off the line, the field heads back towards it in both views.
      const Eigen::Vector3d off = x + Eigen::Vector3d(0.3, -0.2, 0.1);
      const Eigen::Vector3d back = field.Lifted(off);
      const Eigen::Vector3d to_line = (x + u * u.dot(off - x)) - off;
      EXPECT_GT(back.normalized().dot(to_line.normalized()), 0.4) << combine;
    }
  }
  // The mean of a general direction's views is biased by the views' unit
  // lengths, which "intersect" avoids.
  options.combine = "average";
  std::vector<AttractorGraph2D> graphs;
  for (int v = 0; v < 2; ++v)
    graphs.push_back(ProjectedSegment(set, v, x - 0.6 * general, x + 0.6 * general));
  EXPECT_GT(AngleDeg(AttractorDirectionField(set, graphs, bounds, options).Lifted(x), general),
            2.0);
}

// A field of two orthographic views of one branch, over [-1, 1]^3 sampled
// `resolution` cells across.
struct OneBranchField {
  ImageSet set = TwoOrthographicViews();
  Eigen::AlignedBox3d bounds{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  AttractorFieldOptions options;
  std::vector<AttractorGraph2D> graphs;

  explicit OneBranchField(int resolution) {
    options.resolution_3d = resolution;
    for (int v = 0; v < 2; ++v) {
      graphs.push_back(
          ProjectedSegment(set, v, Eigen::Vector3d(0.2, 0.1, 0.8), Eigen::Vector3d::Zero()));
    }
  }
  AttractorDirectionField Make() const { return {set, graphs, bounds, options}; }
};

TEST(AttractorDirectionField, FillsOnlyTheSamplesItIsAskedAboutWithTheSameValues) {
  const OneBranchField branch(48);
  const AttractorDirectionField lazy = branch.Make();
  EXPECT_EQ(lazy.FilledSamples(), 0);
  const Eigen::Vector3d x(0.31, -0.22, 0.47);
  const Eigen::Vector3d at_x = lazy.Direction(x);
  EXPECT_EQ(lazy.FilledSamples(), 8);  // one cell's corners
  EXPECT_LT(lazy.FilledSamples(), lazy.NumSamples());
  // Filled in another order (every sample first), the field is the same.
  const AttractorDirectionField whole = branch.Make();
  for (double z = -1.0; z <= 1.0; z += 0.05) whole.Direction(Eigen::Vector3d(-0.9, 0.9, z));
  EXPECT_EQ(whole.Direction(x), at_x);
}

// Threads asking for the same cells at once (each claims some corners and
// waits for those another is filling) see the field one thread sees.
TEST(AttractorDirectionField, FilledConcurrentlyLikeSerially) {
  const OneBranchField branch(24);
  // Points in a small box, each asked for 8 times, in an order that puts
  // neighbours in different tasks.
  std::vector<Eigen::Vector3d> points;
  for (int repeat = 0; repeat < 8; ++repeat) {
    for (int k = 0; k < 4000; ++k) {
      const int i = (k * 7919) % 4000;
      points.emplace_back(-0.3 + 0.6 * (i % 20) / 20.0, -0.3 + 0.6 * (i / 20 % 20) / 20.0,
                          -0.3 + 0.6 * (i / 400) / 10.0);
    }
  }
  const AttractorDirectionField serial = branch.Make();
  std::vector<Eigen::Vector3d> expected(points.size());
  for (size_t p = 0; p < points.size(); ++p) expected[p] = serial.Direction(points[p]);
  const AttractorDirectionField shared = branch.Make();
  std::vector<Eigen::Vector3d> seen(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t p = range.begin(); p < range.end(); ++p) {
                        seen[p] = shared.Direction(points[p]);
                      }
                    });
  EXPECT_EQ(shared.FilledSamples(), serial.FilledSamples());
  for (size_t p = 0; p < points.size(); ++p) ASSERT_EQ(seen[p], expected[p]) << p;
}

TEST(AttractorDirectionField, PinholeLiftingFollowsTheImagePlane) {
  ImageSet set;
  set.cameras[1] = Camera::Pinhole(640, 480, 500);
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
  set.views.push_back({1, "p.png", 1, Rigid3d(rotation, {0.1, -0.2, 4})});
  const Eigen::Vector3d x(0.3, 0.1, 0.2);
  // A displacement parallel to the image plane: its image is the graph.
  const Eigen::Matrix3d world_from_cam = rotation.inverse().toRotationMatrix();
  const Eigen::Vector3d along = world_from_cam * Eigen::Vector3d(0.6, 0.8, 0);
  const std::vector<AttractorGraph2D> graphs = {
      ProjectedSegment(set, 0, x - 0.3 * along, x + 0.3 * along)};
  AttractorFieldOptions options;
  options.resolution = 320;
  options.resolution_3d = 48;
  options.falloff = 0.1;
  const AttractorDirectionField field(
      set, graphs, Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)),
      options);
  EXPECT_LT(AngleDeg(field.Lifted(x), along), 0.5);
  EXPECT_NEAR(field.Lifted(x).norm(), 1.0, 0.02);
  // Behind the camera or outside the image: no direction.
  EXPECT_EQ(field.Lifted(Eigen::Vector3d(-0.1, 0.2, -10)), Eigen::Vector3d::Zero());
}

TEST(AttractorDirectionField, ViewsWithoutGraphsAndBadInput) {
  const ImageSet set = TwoOrthographicViews();
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  AttractorFieldOptions options;
  const std::vector<AttractorGraph2D> none(2);
  const AttractorDirectionField empty(set, none, bounds, options);
  EXPECT_EQ(empty.NumViewsWithGraphs(), 0);
  EXPECT_EQ(empty.Direction(Eigen::Vector3d(0.2, 0, 0)), Eigen::Vector3d::Zero());
  // A graph on a half-size copy of the photo is rescaled.
  std::vector<AttractorGraph2D> half = {ProjectedSegment(set, 0, {0, 0, 0.8}, {0, 0, -0.8}), {}};
  half[0] = half[0].Scaled(0.5);
  const AttractorDirectionField scaled(set, half, bounds, options);
  EXPECT_LT(AngleDeg(scaled.Lifted(Eigen::Vector3d(0, 0, 0.1)), {0, 0, -1}), 0.5);
  // Wrong count, wrong aspect, bad options.
  EXPECT_THROW(AttractorDirectionField(set, std::vector<AttractorGraph2D>(1), bounds, options),
               InputError);
  std::vector<AttractorGraph2D> squashed = half;
  squashed[0].height = 40;
  EXPECT_THROW(AttractorDirectionField(set, squashed, bounds, options), InputError);
  AttractorFieldOptions bad = options;
  bad.blend = "quadratic";
  EXPECT_THROW(bad.Check(), InputError);
  bad = options;
  bad.constant_h = 1.0;
  EXPECT_THROW(bad.Check(), InputError);
  bad = options;
  bad.combine = "sum";
  EXPECT_THROW(bad.Check(), InputError);
}

// The flow steered by an attractor field: the same skeleton whatever the
// number of threads, and it follows the graphs (a trunk leaning towards +x).
TEST(AttractorDirectionField, SteeredFlowIsDeterministicAndFollowsTheGraphs) {
  const ImageSet set = TwoOrthographicViews();
  DensityGrid density(0.05, Eigen::Vector3d::Zero());
  for (int k = 0; k < 30; ++k)
    for (int j = -8; j <= 8; ++j)
      for (int i = -8; i <= 8; ++i) density.SetValue({i, j, k}, k > 15 ? 0.3f : 0.05f);
  // The graphs: a straight trunk from the base to (0.3, 0, 1.4).
  const Eigen::Vector3d base(0, 0, -0.025), top(0.3, 0, 1.4);
  std::vector<AttractorGraph2D> graphs;
  for (int v = 0; v < 2; ++v) graphs.push_back(ProjectedSegment(set, v, top, base));
  AttractorFieldOptions options;
  options.resolution_3d = 48;
  const AttractorDirectionField field(set, graphs, density.ActiveWorldBounds(), options);
  ParticleFlowOptions flow;
  flow.num_particles = 600;
  SkeletonGraph skeletons[2];
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    skeletons[threads - 1] = SimulateParticleFlow(density, base, field, flow, nullptr, nullptr);
  }
  ASSERT_EQ(skeletons[0].NumNodes(), skeletons[1].NumNodes());
  for (int i = 0; i < skeletons[0].NumNodes(); ++i) {
    EXPECT_EQ(skeletons[0].nodes[i].position, skeletons[1].nodes[i].position) << i;
    EXPECT_EQ(skeletons[0].nodes[i].parent_idx, skeletons[1].nodes[i].parent_idx) << i;
  }
  // The trunk (the chain carrying most strands) leans with the graph: at
  // 0.7 m its x is near the graph's 0.153, where the unsteered flow's axis
  // through the base is at 0.
  const SkeletonGraph unsteered =
      SimulateParticleFlow(density, base, ConstantDirectionField(), flow, nullptr, nullptr);
  const auto trunk_x_at = [](const SkeletonGraph& skeleton, double z) {
    const BranchAxis trunk = skeleton.BranchAxes().front();
    for (size_t k = 1; k < trunk.size(); ++k) {
      const Eigen::Vector3d a = skeleton.nodes[trunk[k - 1]].position;
      const Eigen::Vector3d b = skeleton.nodes[trunk[k]].position;
      if ((a.z() - z) * (b.z() - z) <= 0 && a.z() != b.z())
        return a.x() + (b.x() - a.x()) * (z - a.z()) / (b.z() - a.z());
    }
    return std::nan("");
  };
  const double steered_x = trunk_x_at(skeletons[0], 0.7), plain_x = trunk_x_at(unsteered, 0.7);
  std::printf("trunk x at z = 0.7: steered %.3f, unsteered %.3f (graph 0.153)\n", steered_x,
              plain_x);
  EXPECT_NEAR(steered_x, 0.153, 0.05);
  EXPECT_LT(std::abs(plain_x), 0.05);
}

}  // namespace
}  // namespace sylva
