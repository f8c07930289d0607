#include "simulate/particle_flow.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <utility>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kVoxel = 0.1;  // metres

// A simple tree-like density: a vertical trunk column (3 x 3 voxels, opacity
// 0.6) from z = 0 to 2 m under a spherical crown (radius 0.9 m, centre at
// 2.6 m, opacity 0.3), the trunk's bottom centre at the origin.
DensityGrid ColumnAndCrown() {
  DensityGrid grid(kVoxel, Eigen::Vector3d(0, 0, kVoxel / 2));
  for (int k = 0; k < 36; ++k)
    for (int j = -10; j <= 10; ++j)
      for (int i = -10; i <= 10; ++i) {
        const Eigen::Vector3d p = grid.WorldFromIndex(Eigen::Vector3d(i, j, k));
        float alpha = 0.0f;
        if ((p - Eigen::Vector3d(0, 0, 2.6)).norm() < 0.9) alpha = 0.3f;
        if (std::abs(i) <= 1 && std::abs(j) <= 1 && p.z() < 2.0) alpha = 0.6f;
        grid.SetValue({i, j, k}, alpha);
      }
  return grid;
}

// Two 6^3 blobs of opacity 0.8 (x < 0) and 0.2 (x > 0) on a low bar.
DensityGrid TwoBlobs() {
  DensityGrid grid(kVoxel, Eigen::Vector3d(0, 0, 0));
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) {
        grid.SetValue({i - 10, j, k + 5}, 0.8f);
        grid.SetValue({i + 10, j, k + 5}, 0.2f);
      }
  return grid;
}

const Eigen::Vector3d kBase(0, 0, 0);

ParticleFlowOptions SmallOptions() {
  ParticleFlowOptions options;
  options.num_particles = 400;
  return options;
}

SkeletonGraph Simulate(const ParticleFlowOptions& options, ParticleFlowSummary* summary = nullptr,
                       const DirectionField& field = ConstantDirectionField(),
                       SkeletonGraph* raw = nullptr) {
  return SimulateParticleFlow(ColumnAndCrown(), kBase, field, options, nullptr, summary, raw);
}

// Every node with children carries the sum of its children's strands; tips
// carry one seeded particle each.
void ExpectMassConserved(const SkeletonGraph& skeleton, int num_particles) {
  ASSERT_NO_THROW(skeleton.Check());
  ASSERT_EQ(skeleton.RootIdx(), 0);
  EXPECT_EQ(skeleton.nodes[0].strands, num_particles);
  const std::vector<std::vector<int>> children = skeleton.Children();
  int tips = 0;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (children[i].empty()) {
      EXPECT_EQ(skeleton.nodes[i].strands, 1) << "tip " << i;
      ++tips;
      continue;
    }
    int sum = 0;
    for (int child : children[i]) sum += skeleton.nodes[child].strands;
    EXPECT_EQ(skeleton.nodes[i].strands, sum) << "node " << i;
  }
  EXPECT_EQ(tips, num_particles);
}

// Seeds in the dense blob (opacity 0.8) and the sparse one (0.2) of
// TwoBlobs, seeded with `exponent`.
std::pair<int, int> SeedsPerBlob(double exponent) {
  ParticleFlowOptions options;
  options.num_particles = 5000;
  options.max_iterations = 0;
  options.seed_exponent = exponent;
  SkeletonGraph raw;
  SimulateParticleFlow(TwoBlobs(), Eigen::Vector3d(0.05, 0.25, 0.45), ConstantDirectionField(),
                       options, nullptr, nullptr, &raw);
  int dense = 0, sparse = 0;
  for (int tip : raw.Tips()) (raw.nodes[tip].position.x() < 0 ? dense : sparse) += 1;
  return {dense, sparse};
}

TEST(ParticleFlowTest, SeedExponentEvensTheSeedsOut) {
  // opacity^0.5: 0.894 : 0.447, so 3333 : 1667 (sigma ~33); opacity^0: the
  // voxels alike, 2500 : 2500.
  const auto [dense, sparse] = SeedsPerBlob(0.5);
  EXPECT_EQ(dense + sparse, 5000);
  EXPECT_NEAR(dense, 3333, 170);
  EXPECT_NEAR(SeedsPerBlob(0.0).first, 2500, 180);
  EXPECT_NEAR(SeedsPerBlob(1.0).first, 4000, 150);
}

TEST(ParticleFlowTest, SeedingFollowsTheDensity) {
  ParticleFlowOptions options;
  options.num_particles = 5000;
  options.max_iterations = 0;  // the tips of the raw traces are the seeds
  SkeletonGraph raw;
  ParticleFlowSummary summary;
  const Eigen::Vector3d base(0.05, 0.25, 0.45);
  SimulateParticleFlow(TwoBlobs(), base, ConstantDirectionField(), options, nullptr, &summary,
                       &raw);
  EXPECT_EQ(summary.unfinished, 5000);
  int dense = 0, sparse = 0;
  for (int tip : raw.Tips()) {
    const Eigen::Vector3d& p = raw.nodes[tip].position;
    // Every seed lies inside its blob.
    ASSERT_GE(p.z(), 0.45);
    ASSERT_LE(p.z(), 1.05);
    (p.x() < 0 ? dense : sparse) += 1;
  }
  EXPECT_EQ(dense + sparse, 5000);
  // Expected 4000 : 1000; binomial sigma ~28, so 5 sigma is ~150.
  EXPECT_NEAR(dense, 4000, 150);
}

TEST(ParticleFlowTest, ReturnsOneRootedTreeThatConservesMass) {
  ParticleFlowSummary summary;
  SkeletonGraph raw;
  const SkeletonGraph skeleton = Simulate(SmallOptions(), &summary, ConstantDirectionField(), &raw);
  ExpectMassConserved(skeleton, 400);
  ExpectMassConserved(raw, 400);
  EXPECT_EQ(skeleton.nodes[0].position, kBase);
  EXPECT_EQ(skeleton.radius_source, "unknown");
  for (const SkeletonNode& node : skeleton.nodes) EXPECT_EQ(node.radius, 0.0);
  // Parents are listed before their children.
  for (int i = 1; i < skeleton.NumNodes(); ++i) EXPECT_LT(skeleton.nodes[i].parent_idx, i);
  EXPECT_GT(summary.merges, 0);
  EXPECT_LT(skeleton.NumNodes(), raw.NumNodes());
  EXPECT_EQ(summary.raw_nodes, raw.NumNodes());
  EXPECT_EQ(summary.skeleton_nodes, skeleton.NumNodes());
  // Orders are assigned: the trunk is order 0 and branches exist.
  int max_order = 0;
  for (const SkeletonNode& node : skeleton.nodes) max_order = std::max(max_order, node.order);
  EXPECT_GT(max_order, 0);
  EXPECT_FALSE(summary.BriefReport().empty());
}

TEST(ParticleFlowTest, AllParticlesReachTheBase) {
  ParticleFlowSummary summary;
  const SkeletonGraph skeleton = Simulate(SmallOptions(), &summary);
  EXPECT_EQ(summary.reached_base, 400) << summary.BriefReport();
  EXPECT_EQ(summary.unfinished, 0);
  // One query per particle and step, absorbed particles included.
  EXPECT_EQ(summary.neighbor_queries, summary.particle_steps + summary.merges);
  // The traces gather into one trunk, which runs inside the trunk column:
  // the root's heaviest child carries nearly every particle.
  int heaviest = 0;
  const std::vector<std::vector<int>> children = skeleton.Children();
  for (int child : children[0]) {
    heaviest = std::max(heaviest, skeleton.nodes[child].strands);
  }
  EXPECT_GE(heaviest, 0.9 * 400);
  for (const Eigen::Vector3d& p : skeleton.SamplePoints(0.05)) {
    if (p.z() < 1.0) {
      EXPECT_LT(p.head<2>().norm(), 0.3) << p.transpose();
    }
  }
}

TEST(ParticleFlowTest, JoiningFinishedTracesMakesOneTrunk) {
  ParticleFlowOptions options = SmallOptions();
  ParticleFlowSummary joined, separate;
  const SkeletonGraph one = Simulate(options, &joined);
  options.join_finished_traces = false;
  const SkeletonGraph many = Simulate(options, &separate);
  ExpectMassConserved(many, 400);
  EXPECT_GT(joined.trace_joins, 0);
  EXPECT_EQ(separate.trace_joins, 0);
  EXPECT_LT(one.Children()[0].size(), many.Children()[0].size());
}

// Bundles that come upon the trace of one still flowing ahead of them, and
// move along it, join it: one trace instead of two side by side, and mass
// conserved (the bundle ahead carries them from then on). Only traces
// moved along are joined: at a right angle and less, more join.
TEST(ParticleFlowTest, JoiningFlowingTracesLaysLessWoodAndConservesMass) {
  ParticleFlowOptions options = SmallOptions();
  options.join_flowing_traces = true;
  ParticleFlowSummary joined, separate, wide;
  const SkeletonGraph one = Simulate(options, &joined);
  ExpectMassConserved(one, 400);
  options.join_flowing_traces = false;
  const SkeletonGraph two = Simulate(options, &separate);
  EXPECT_GT(joined.flowing_joins, 10);
  EXPECT_EQ(separate.flowing_joins, 0);
  // 97.1 m against 105.7 m.
  EXPECT_LT(one.TotalLength(), 0.95 * two.TotalLength());
  options.join_flowing_traces = true;
  options.flowing_join_angle_deg = 90;
  ExpectMassConserved(Simulate(options, &wide), 400);
  EXPECT_GT(wide.flowing_joins, joined.flowing_joins);
  options.flowing_join_angle_deg = 181;
  EXPECT_THROW(options.Check(), InputError);
}

TEST(ParticleFlowTest, UnfinishedParticlesAreJoinedToTheRoot) {
  ParticleFlowOptions options = SmallOptions();
  options.max_iterations = 5;
  ParticleFlowSummary summary;
  const SkeletonGraph skeleton = Simulate(options, &summary);
  EXPECT_GT(summary.unfinished, 0);
  EXPECT_EQ(summary.unfinished + summary.reached_base, 400);
  ExpectMassConserved(skeleton, 400);
}

void ExpectIdentical(const SkeletonGraph& a, const SkeletonGraph& b) {
  ASSERT_EQ(a.NumNodes(), b.NumNodes());
  for (int i = 0; i < a.NumNodes(); ++i) {
    ASSERT_EQ(a.nodes[i].position, b.nodes[i].position) << "node " << i;
    ASSERT_EQ(a.nodes[i].parent_idx, b.nodes[i].parent_idx) << "node " << i;
    ASSERT_EQ(a.nodes[i].strands, b.nodes[i].strands) << "node " << i;
  }
}

TEST(ParticleFlowTest, IsDeterministicBySeedWhateverTheThreadsAndNeighbourSearch) {
  const SkeletonGraph first = Simulate(SmallOptions());
  ExpectIdentical(first, Simulate(SmallOptions()));
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    ExpectIdentical(first, Simulate(SmallOptions()));
  }
  // Every structure finds the same neighbours, so the skeleton is the same.
  for (const char* search : {"embree", "brute_force"}) {
    ParticleFlowOptions options = SmallOptions();
    options.neighbor_search = search;
    ExpectIdentical(first, Simulate(options));
  }
  ParticleFlowOptions other_seed = SmallOptions();
  other_seed.seed = 2;
  const SkeletonGraph second = Simulate(other_seed);
  bool differs = second.NumNodes() != first.NumNodes();
  for (int i = 0; !differs && i < first.NumNodes(); ++i) {
    differs = first.nodes[i].position != second.nodes[i].position;
  }
  EXPECT_TRUE(differs);
}

// Mean x of where the particles flowed: trace nodes weighted by the
// particles passing them.
double FlowMeanX(const SkeletonGraph& raw_traces) {
  double sum = 0.0, weight = 0.0;
  for (const SkeletonNode& node : raw_traces.nodes) {
    sum += node.strands * node.position.x();
    weight += node.strands;
  }
  return sum / weight;
}

TEST(ParticleFlowTest, TheDirectionFieldBendsTheTraces) {
  SkeletonGraph straight, bent, ignored;
  const ConstantDirectionField sideways(Eigen::Vector3d(1, 0, 0));
  Simulate(SmallOptions(), nullptr, ConstantDirectionField(), &straight);
  ExpectMassConserved(Simulate(SmallOptions(), nullptr, sideways, &bent), 400);
  // Without a field the flow is symmetric about the trunk; pushed along +x
  // it swings out (the pull back to the trunk axis limits how far).
  EXPECT_NEAR(FlowMeanX(straight), 0.0, 0.2 * kVoxel);
  EXPECT_GT(FlowMeanX(bent) - FlowMeanX(straight), 1 * kVoxel);
  ParticleFlowOptions no_weight = SmallOptions();
  no_weight.field_weight = 0;
  Simulate(no_weight, nullptr, sideways, &ignored);
  ExpectIdentical(straight, ignored);
}

void ExpectInputError(const std::function<void()>& run, const std::string& source,
                      const std::string& words) {
  try {
    run();
    ADD_FAILURE() << "expected InputError from " << source;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), source);
    EXPECT_NE(error.message().find(words), std::string::npos) << error.what();
  }
}

TEST(ParticleFlowTest, OptionsCheckNamesTheField) {
  const auto with = [](const std::function<void(ParticleFlowOptions*)>& change) {
    return [change] {
      ParticleFlowOptions options;
      change(&options);
      options.Check();
    };
  };
  EXPECT_NO_THROW(ParticleFlowOptions().Check());
  ExpectInputError(with([](auto* o) { o->num_particles = 0; }), "ParticleFlow.num_particles",
                   "between 1");
  ExpectInputError(with([](auto* o) { o->neighbor_radius = -1; }), "ParticleFlow.neighbor_radius",
                   "positive");
  ExpectInputError(with([](auto* o) { o->damping = 0; }), "ParticleFlow.damping", "positive");
  ExpectInputError(with([](auto* o) { o->seed_exponent = -0.5; }), "ParticleFlow.seed_exponent",
                   "between 0 and 4");
  ExpectInputError(with([](auto* o) { o->merge_distance = NAN; }), "ParticleFlow.merge_distance",
                   ">= 0");
  ExpectInputError(with([](auto* o) { o->initial_step = 5; }), "ParticleFlow.initial_step",
                   "within");
  ExpectInputError(with([](auto* o) { o->neighbor_search = "octree"; }),
                   "ParticleFlow.neighbor_search", "octree");
  ExpectInputError(
      [] {
        TreeBaseOptions{0.05, 0.5, 8, 0}.Check();
      },
      "TreeBase.slab_voxels", ">= 1");
}

TEST(ParticleFlowTest, BadInputsAreInputErrors) {
  ExpectInputError(
      [] {
        SimulateParticleFlow(DensityGrid(kVoxel, Eigen::Vector3d::Zero()), kBase,
                             ConstantDirectionField(), ParticleFlowOptions(), nullptr, nullptr);
      },
      "density", "no active voxels");
  ExpectInputError(
      [] {
        SimulateParticleFlow(ColumnAndCrown(), Eigen::Vector3d(0, 0, -5), ConstantDirectionField(),
                             ParticleFlowOptions(), nullptr, nullptr);
      },
      "base", "outside");
  ExpectInputError([] { EstimateTreeBase(DensityGrid(kVoxel, Eigen::Vector3d::Zero())); },
                   "density", "tree base");
}

// Asks to cancel on the first progress report.
class CancellingReporter : public ProgressReporter {
 public:
  void Update(std::string_view, double) override {
    ++updates;
    RequestCancel();
  }
  int updates = 0;
};

TEST(ParticleFlowTest, CancellationStopsTheRun) {
  CancellingReporter reporter;
  EXPECT_THROW(SimulateParticleFlow(ColumnAndCrown(), kBase, ConstantDirectionField(),
                                    SmallOptions(), &reporter, nullptr),
               Cancelled);
  EXPECT_GE(reporter.updates, 1);
}

TEST(ParticleFlowTest, EstimatesTheBaseAtTheBottomOfTheTrunk) {
  DensityGrid density = ColumnAndCrown();
  EXPECT_NEAR((EstimateTreeBase(density) - kBase).norm(), 0.0, 1e-9);
  // A few blurred voxels under the trunk do not lower the base.
  density.SetValue({0, 0, -1}, 0.3f);
  density.SetValue({1, 0, -1}, 0.2f);
  EXPECT_NEAR((EstimateTreeBase(density) - kBase).norm(), 0.0, 1e-9);
  // A full layer does.
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) density.SetValue({i, j, -1}, 0.6f);
  EXPECT_NEAR(EstimateTreeBase(density).z(), -kVoxel, 1e-9);
}

}  // namespace
}  // namespace sylva
