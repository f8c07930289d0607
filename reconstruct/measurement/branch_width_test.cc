#include "reconstruct/measurement/branch_width.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "core/util/check.h"
#include "core/util/statistics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "mesh/allometry.h"

namespace sylva {
namespace {

// A leafless synthetic tree seen from 6 views.
SyntheticDataset LeaflessTree() {
  SyntheticDatasetOptions options;
  options.seed = 3;
  options.num_views = 6;
  options.num_held_out = 0;
  options.image_size = 768;
  options.samples_per_axis = 2;
  options.tree.leaves_per_cluster = 0;
  return MakeSyntheticDataset(options);
}

// Median over the edges of each branch order of radius / true radius.
std::map<int, double> RatioByOrder(const SkeletonGraph& skeleton, const SkeletonGraph& truth) {
  std::map<int, std::vector<double>> ratios;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (skeleton.nodes[i].parent_idx < 0) continue;
    ratios[truth.nodes[i].order].push_back(skeleton.nodes[i].radius / truth.nodes[i].radius);
  }
  std::map<int, double> medians;
  for (const auto& [order, values] : ratios) medians[order] = Median(values);
  return medians;
}

// The true skeleton with pipe-model radii at a third of the true trunk's
// scale: the measurement must bring the trunk and the main branches back.
TEST(BranchWidthTest, MeasuresALeaflessTreesBranches) {
  const SyntheticDataset data = LeaflessTree();
  const SkeletonGraph& truth = data.tree.skeleton;
  SkeletonGraph skeleton = truth;
  AllometryOptions allometry;
  allometry.trunk_radius = truth.nodes[truth.RootIdx()].radius / 3.0;
  allometry.min_radius = 0.0;
  AssignPipeModelRadii(allometry, &skeleton);
  const std::map<int, double> before = RatioByOrder(skeleton, truth);

  const BranchWidthSummary summary =
      MeasureBranchRadii(data.image_set, data.mattes, true, false, BranchWidthOptions(), &skeleton);
  const std::map<int, double> after = RatioByOrder(skeleton, truth);
  std::printf("%s\n", summary.BriefReport().c_str());
  for (const auto& [order, ratio] : after) {
    std::printf("order %d: radius / truth %.3f before, %.3f after\n", order, before.at(order),
                ratio);
  }
  EXPECT_EQ(skeleton.radius_source, kMattesMeasured);
  EXPECT_GT(summary.measured_length, 0.5 * summary.total_length);
  // Measured 1.003, 0.956, 0.925, 1.015 against 0.34-0.51 before.
  EXPECT_NEAR(after.at(0), 1.0, 0.1);   // the trunk
  EXPECT_NEAR(after.at(1), 1.0, 0.15);  // its branches
  EXPECT_NEAR(after.at(2), 1.0, 0.2);
  EXPECT_NEAR(after.at(3), 1.0, 0.2);
  skeleton.Check();
}

TEST(BranchWidthTest, ModesAndAGivenTrunk) {
  const SyntheticDataset data = LeaflessTree();
  SkeletonGraph prior = data.tree.skeleton;
  AllometryOptions allometry;
  allometry.trunk_radius = 0.05;
  AssignPipeModelRadii(allometry, &prior);
  BranchWidthOptions options;
  // auto: a leafy plant keeps the prior.
  SkeletonGraph leafy = prior;
  EXPECT_EQ(
      MeasureBranchRadii(data.image_set, data.mattes, false, false, options, &leafy).measured_axes,
      0);
  EXPECT_EQ(leafy.radius_source, kAllometricPrior);
  for (int i = 0; i < prior.NumNodes(); ++i)
    EXPECT_EQ(leafy.nodes[i].radius, prior.nodes[i].radius);
  // A given trunk keeps its radii; its branches are still measured.
  SkeletonGraph kept = prior;
  const BranchWidthSummary summary =
      MeasureBranchRadii(data.image_set, data.mattes, true, true, options, &kept);
  EXPECT_EQ(summary.trunk_scale, 1.0);
  EXPECT_GT(summary.measured_axes, 0);
  EXPECT_EQ(kept.nodes[kept.RootIdx()].radius, prior.nodes[prior.RootIdx()].radius);
  // Bad options are named.
  options.mode = "sometimes";
  EXPECT_THROW(MeasureBranchRadii(data.image_set, data.mattes, true, false, options, &kept),
               InputError);
}

// Empty mattes measure nothing: the prior stays, labelled as such.
TEST(BranchWidthTest, EmptyMattesKeepThePrior) {
  const SyntheticDataset data = LeaflessTree();
  SkeletonGraph skeleton = data.tree.skeleton;
  AssignPipeModelRadii(AllometryOptions(), &skeleton);
  const SkeletonGraph prior = skeleton;
  std::vector<FloatImage> empty;
  for (const FloatImage& matte : data.mattes) {
    empty.emplace_back(matte.width(), matte.height(), 1, 0.0f);
  }
  const BranchWidthSummary summary =
      MeasureBranchRadii(data.image_set, empty, true, false, BranchWidthOptions(), &skeleton);
  EXPECT_EQ(summary.measured_axes, 0);
  EXPECT_EQ(skeleton.radius_source, kAllometricPrior);
  EXPECT_EQ(skeleton.nodes[5].radius, prior.nodes[5].radius);
}

}  // namespace
}  // namespace sylva
