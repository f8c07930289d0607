#include "mesh/trunk_width.h"

#include <gtest/gtest.h>

#include <cstdio>

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
        MeasureTrunkWidth(data.image_set, data.mattes, data.tree.skeleton, height);
    const double truth = TrueTrunkRadius(data.tree.skeleton, height);
    EXPECT_GE(width.num_measurements, options.num_views) << SyntheticCameraKindName(kind);
    EXPECT_NEAR(width.radius, truth, 0.2 * truth) << SyntheticCameraKindName(kind);
  }
}

// Pinhole views of the synthetic tree, none held out.
SyntheticDataset PinholeViews(int num_views, int image_size) {
  SyntheticDatasetOptions options;
  options.num_views = num_views;
  options.num_held_out = 0;
  options.image_size = image_size;
  return MakeSyntheticDataset(options);
}

// A pot (or a stake and its clips) beside the trunk's foot, as wide as 15 %
// of the height and up to 12 % of it, painted into every matte: the lowest
// sections measure the pot, those above it the trunk, and the trunk is the
// smallest base radius they imply (the median over the lowest heights
// measured the pot). Along the true skeleton's trunk (its tip counts as
// strands).
TEST(TrunkWidthTest, APotAtTheFootIsNotTheTrunk) {
  const SyntheticDataset data = PinholeViews(4, 384);
  const double height = data.tree.mesh.Bounds().sizes().z();
  std::vector<FloatImage> potted = data.mattes;
  for (int v = 0; v < data.image_set.NumViews(); ++v) {
    const View& view = data.image_set.views[v];
    const Camera& camera = data.image_set.CameraOf(view);
    const Eigen::Vector3d foot_in_cam = view.cam_from_world * Eigen::Vector3d::Zero();
    const Eigen::Vector2d foot = camera.ImgFromCam(foot_in_cam);
    const Eigen::Vector2d top =
        camera.ImgFromCam(view.cam_from_world * Eigen::Vector3d(0, 0, 0.12 * height));
    const double half_width = 0.075 * height / camera.WorldPerPixel(foot_in_cam);
    for (int y = static_cast<int>(top.y()); y <= static_cast<int>(foot.y()); ++y) {
      for (int x = static_cast<int>(foot.x() - half_width); x <= foot.x() + half_width; ++x) {
        if (x >= 0 && y >= 0 && x < potted[v].width() && y < potted[v].height()) {
          potted[v].at(x, y) = 1.0f;
        }
      }
    }
  }
  const double truth = TrueTrunkRadius(data.tree.skeleton, height);
  const TrunkWidth potted_width =
      MeasureTrunkWidth(data.image_set, potted, data.tree.skeleton, height);
  EXPECT_NEAR(potted_width.radius, truth, 0.25 * truth);
  // Without the pot, the same.
  const TrunkWidth clean =
      MeasureTrunkWidth(data.image_set, data.mattes, data.tree.skeleton, height);
  EXPECT_NEAR(clean.radius, truth, 0.25 * truth);
  std::printf("truth %.4f; potted %.4f; clean %.4f\n", truth, potted_width.radius, clean.radius);
}

TEST(TrunkWidthTest, NothingMeasurableGivesZero) {
  const SyntheticDataset data = PinholeViews(2, 64);
  std::vector<FloatImage> empty(2, FloatImage(64, 64, 1, 0.0f));
  const TrunkWidth width = MeasureTrunkWidth(data.image_set, empty, data.tree.skeleton, 6.0);
  EXPECT_EQ(width.num_measurements, 0);
  EXPECT_EQ(width.radius, 0.0);
}

// Given, else measured, else the fallback fraction of the height; `how`
// says which.
TEST(TrunkWidthTest, ChooseTrunkRadiusGivenMeasuredOrFallback) {
  const SyntheticDataset data = PinholeViews(2, 384);
  const double height = data.tree.mesh.Bounds().sizes().z();
  const SkeletonGraph& skeleton = data.tree.skeleton;
  const TrunkRadius given =
      ChooseTrunkRadius(data.image_set, data.mattes, skeleton, height, 0.3, 0.02, 2.0);
  EXPECT_EQ(given.radius, 0.3);
  EXPECT_EQ(given.how, "given");
  const TrunkRadius measured =
      ChooseTrunkRadius(data.image_set, data.mattes, skeleton, height, 0.0, 0.02, 2.0);
  const TrunkWidth width = MeasureTrunkWidth(data.image_set, data.mattes, skeleton, height);
  ASSERT_GT(width.radius, 0);
  EXPECT_EQ(measured.radius, width.radius);
  EXPECT_EQ(measured.how,
            "measured in " + std::to_string(width.num_measurements) + " matte sections");
  const std::vector<FloatImage> empty(2, FloatImage(384, 384, 1, 0.0f));
  const TrunkRadius fallback =
      ChooseTrunkRadius(data.image_set, empty, skeleton, height, 0.0, 0.02, 2.0);
  EXPECT_DOUBLE_EQ(fallback.radius, 0.02 * height);
  EXPECT_EQ(fallback.how, "not measurable in the mattes; 0.02 x height");
}

}  // namespace
}  // namespace sylva
