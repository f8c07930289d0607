#include "mesh/allometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

// 0 -> 1 -> {2 -> {4, 5}, 3 -> {6, 7, 8}}; strands conserved at every junction
// (a trifurcation included). Nodes are stored children first in places, to
// check that nothing assumes parents come first.
SkeletonGraph ConsistentTree() {
  SkeletonGraph skeleton;
  skeleton.nodes.resize(9);
  const int parents[] = {-1, 0, 1, 1, 2, 2, 3, 3, 3};
  const int strands[] = {20, 20, 9, 11, 5, 4, 6, 3, 2};
  for (int i = 0; i < 9; ++i) {
    skeleton.nodes[i].parent_idx = parents[i];
    skeleton.nodes[i].strands = strands[i];
    skeleton.nodes[i].position = Eigen::Vector3d(0.1 * i, 0.0, 1.0 * i);
  }
  return skeleton;
}

// The same tree with its node storage reversed (children before parents).
SkeletonGraph Reversed(const SkeletonGraph& skeleton) {
  SkeletonGraph reversed = skeleton;
  const int n = skeleton.NumNodes();
  for (int i = 0; i < n; ++i) {
    reversed.nodes[n - 1 - i] = skeleton.nodes[i];
    const int parent = skeleton.nodes[i].parent_idx;
    reversed.nodes[n - 1 - i].parent_idx = parent < 0 ? -1 : n - 1 - parent;
  }
  return reversed;
}

// Max over junctions of |d0^Δ - Σ di^Δ| / d0^Δ.
double WorstJunctionError(const SkeletonGraph& skeleton, double exponent) {
  double worst = 0.0;
  const std::vector<std::vector<int>> children = skeleton.Children();
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (children[i].empty()) continue;
    const double parent = std::pow(2 * skeleton.nodes[i].radius, exponent);
    double sum = 0.0;
    for (int c : children[i]) sum += std::pow(2 * skeleton.nodes[c].radius, exponent);
    worst = std::max(worst, std::abs(parent - sum) / parent);
  }
  return worst;
}

TEST(AllometryTest, JunctionRuleHoldsForLeonardoAndMurray) {
  for (double exponent : {2.0, 2.49, 3.0}) {
    SCOPED_TRACE(exponent);
    SkeletonGraph skeleton = ConsistentTree();
    AllometryOptions options;
    options.diameter_exponent = exponent;
    options.trunk_radius = 0.3;
    options.min_radius = 0.0;
    AssignPipeModelRadii(options, &skeleton);
    EXPECT_LT(WorstJunctionError(skeleton, exponent), 1e-12);
    EXPECT_DOUBLE_EQ(skeleton.nodes[0].radius, 0.3);
    EXPECT_DOUBLE_EQ(skeleton.nodes[1].radius, 0.3);  // carries all strands too
    EXPECT_NEAR(skeleton.nodes[8].radius, 0.3 * std::pow(2.0 / 20.0, 1.0 / exponent), 1e-15);
    EXPECT_EQ(skeleton.radius_source, "allometric prior");
  }
}

TEST(AllometryTest, StorageOrderDoesNotMatter) {
  SkeletonGraph forward = ConsistentTree();
  SkeletonGraph backward = Reversed(forward);
  AllometryOptions options;
  options.diameter_exponent = 2.49;
  AssignPipeModelRadii(options, &forward);
  AssignPipeModelRadii(options, &backward);
  const int n = forward.NumNodes();
  for (int i = 0; i < n; ++i) {
    EXPECT_DOUBLE_EQ(forward.nodes[i].radius, backward.nodes[n - 1 - i].radius) << i;
  }
}

TEST(AllometryTest, UnknownStrandsCountTips) {
  SkeletonGraph skeleton = ConsistentTree();
  for (SkeletonNode& node : skeleton.nodes) node.strands = 0;
  const std::vector<double> strands = EffectivePipeStrands(skeleton);
  const double tips_below[] = {5, 5, 2, 3, 1, 1, 1, 1, 1};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(strands[i], tips_below[i]) << i;
  // Strands themselves are not modified; the junction rule holds on tip counts.
  AllometryOptions options;
  options.min_radius = 0.0;
  AssignPipeModelRadii(options, &skeleton);
  EXPECT_EQ(skeleton.nodes[0].strands, 0);
  EXPECT_LT(WorstJunctionError(skeleton, options.diameter_exponent), 1e-12);
}

TEST(AllometryTest, PartlyKnownStrandsNeverThinTowardsTheBase) {
  SkeletonGraph skeleton = ConsistentTree();
  skeleton.nodes[4].strands = 0;   // unknown tip: one strand
  skeleton.nodes[2].strands = 3;   // fewer than its children (1 + 4): raised to 5
  skeleton.nodes[3].strands = 40;  // more than its children and its parent: kept
  const std::vector<double> strands = EffectivePipeStrands(skeleton);
  EXPECT_EQ(strands[4], 1);
  EXPECT_EQ(strands[2], 5);
  EXPECT_EQ(strands[3], 40);
  EXPECT_EQ(strands[1], 45);
  EXPECT_EQ(strands[0], 45);
  const std::vector<std::vector<int>> children = skeleton.Children();
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    for (int c : children[i]) EXPECT_GE(strands[i], strands[c]);
  }
}

TEST(AllometryTest, MinRadiusRaisesThinEdges) {
  SkeletonGraph skeleton = ConsistentTree();
  AllometryOptions options;
  options.trunk_radius = 1.0;
  options.min_radius = 0.4;  // above sqrt(2/20) = 0.32 and sqrt(3/20) = 0.39
  AssignPipeModelRadii(options, &skeleton);
  EXPECT_DOUBLE_EQ(skeleton.nodes[8].radius, 0.4);
  EXPECT_DOUBLE_EQ(skeleton.nodes[7].radius, 0.4);
  EXPECT_NEAR(skeleton.nodes[5].radius, std::sqrt(4.0 / 20.0), 1e-15);
}

TEST(AllometryTest, EmptySkeletonIsLeftAlone) {
  SkeletonGraph skeleton;
  AssignPipeModelRadii(AllometryOptions(), &skeleton);
  EXPECT_EQ(skeleton.radius_source, "unknown");
}

TEST(AllometryTest, BadOptionsNameTheField) {
  SkeletonGraph skeleton = ConsistentTree();
  AllometryOptions options;
  options.diameter_exponent = 0.5;
  try {
    AssignPipeModelRadii(options, &skeleton);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "Allometry.diameter_exponent");
  }
  options = AllometryOptions();
  options.trunk_radius = -1.0;
  EXPECT_THROW(AssignPipeModelRadii(options, &skeleton), InputError);
  options = AllometryOptions();
  options.min_radius = 2 * options.trunk_radius;
  EXPECT_THROW(AssignPipeModelRadii(options, &skeleton), InputError);
}

}  // namespace
}  // namespace sylva
