#include "mesh/trunk_width.h"

#include <gtest/gtest.h>

#include "datasets/synthetic/synthetic_dataset.h"

namespace sylva {
namespace {

// The synthetic tree's true trunk radius around the sampled heights.
double TrueTrunkRadius(const SkeletonGraph& skeleton, double height) {
  double sum = 0;
  int count = 0;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.order == 0 && node.position.z() > 0.02 * height && node.position.z() < 0.1 * height) {
      sum += node.radius;
      ++count;
    }
  }
  return sum / count;
}

TEST(TrunkWidthTest, MatchesTheSyntheticTrunk) {
  for (const SyntheticCameraKind kind :
       {SyntheticCameraKind::kPinhole, SyntheticCameraKind::kOrthographic}) {
    SyntheticDatasetOptions options;
    options.camera = kind;
    options.num_views = kind == SyntheticCameraKind::kPinhole ? 4 : 2;
    options.num_held_out = 0;
    options.image_size = 384;
    const SyntheticDataset data = MakeSyntheticDataset(options);
    const double height = data.tree.mesh.Bounds().sizes().z();
    const TrunkWidth width =
        MeasureTrunkWidth(data.image_set, data.mattes, Eigen::Vector3d::Zero(), height);
    const double truth = TrueTrunkRadius(data.tree.skeleton, height);
    EXPECT_GE(width.num_measurements, options.num_views) << SyntheticCameraKindName(kind);
    EXPECT_NEAR(width.radius, truth, 0.2 * truth) << SyntheticCameraKindName(kind);
  }
}

// Two pinhole views of the synthetic tree, none held out.
SyntheticDataset TwoViews(int image_size) {
  SyntheticDatasetOptions options;
  options.num_views = 2;
  options.num_held_out = 0;
  options.image_size = image_size;
  return MakeSyntheticDataset(options);
}

TEST(TrunkWidthTest, NothingMeasurableGivesZero) {
  const SyntheticDataset data = TwoViews(64);
  std::vector<FloatImage> empty(2, FloatImage(64, 64, 1, 0.0f));
  const TrunkWidth width = MeasureTrunkWidth(data.image_set, empty, Eigen::Vector3d::Zero(), 6.0);
  EXPECT_EQ(width.num_measurements, 0);
  EXPECT_EQ(width.radius, 0.0);
}

// Given, else measured, else the fallback fraction of the height; `how`
// says which.
TEST(TrunkWidthTest, ChooseTrunkRadiusGivenMeasuredOrFallback) {
  const SyntheticDataset data = TwoViews(384);
  const double height = data.tree.mesh.Bounds().sizes().z();
  const Eigen::Vector3d base = Eigen::Vector3d::Zero();
  const TrunkRadius given = ChooseTrunkRadius(data.image_set, data.mattes, base, height, 0.3, 0.02);
  EXPECT_EQ(given.radius, 0.3);
  EXPECT_EQ(given.how, "given");
  const TrunkRadius measured =
      ChooseTrunkRadius(data.image_set, data.mattes, base, height, 0.0, 0.02);
  const TrunkWidth width = MeasureTrunkWidth(data.image_set, data.mattes, base, height);
  ASSERT_GT(width.radius, 0);
  EXPECT_EQ(measured.radius, width.radius);
  EXPECT_EQ(measured.how,
            "measured in " + std::to_string(width.num_measurements) + " matte sections");
  const std::vector<FloatImage> empty(2, FloatImage(384, 384, 1, 0.0f));
  const TrunkRadius fallback = ChooseTrunkRadius(data.image_set, empty, base, height, 0.0, 0.02);
  EXPECT_DOUBLE_EQ(fallback.radius, 0.02 * height);
  EXPECT_EQ(fallback.how, "not measurable in the mattes; 0.02 x height");
}

}  // namespace
}  // namespace sylva
