#include "reconstruct/matting/matte_set.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "datasets/eval/silhouette_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"

namespace sylva {
namespace {

constexpr int kSize = 160;

// A cabin seen by a fixed camera: a pale wall, orange frame bars down both
// sides and across the top, a black rail across the bottom (below the tree).
struct Cabin {
  FloatImage rgb = FloatImage(kSize, kSize, 3);
  FloatImage rig = FloatImage(kSize, kSize, 1, 0.0f);  // 1 on the frame and rail
};

Cabin MakeCabin() {
  Cabin cabin;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      std::array<float, 3> color = {0.86f, 0.85f, 0.80f};
      const bool frame = x < 7 || x >= kSize - 7 || y < 5;
      const bool rail = y >= kSize - 4;
      if (frame) color = {0.90f, 0.45f, 0.10f};
      if (rail) color = {0.05f, 0.05f, 0.05f};
      for (int c = 0; c < 3; ++c) cabin.rgb.at(x, y, c) = color[c];
      cabin.rig.at(x, y) = frame || rail ? 1.0f : 0.0f;
    }
  }
  return cabin;
}

// The tree of a synthetic photo set over the cabin (its photo's alpha), and
// the matte keying would give: the tree and the rig.
struct CabinPhotos {
  std::vector<FloatImage> photos, mattes, truth;
};

CabinPhotos PhotosInCabin(int num_views) {
  SyntheticDatasetOptions options;
  options.seed = 3;
  options.num_views = num_views;
  options.num_held_out = 0;
  options.image_size = kSize;
  options.samples_per_axis = 2;
  options.margin = 0.1;
  const SyntheticDataset data = MakeSyntheticDataset(options);
  const Cabin cabin = MakeCabin();
  CabinPhotos set;
  for (int v = 0; v < num_views; ++v) {
    FloatImage photo(kSize, kSize, 3), matte(kSize, kSize, 1);
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const float a = data.mattes[v].at(x, y);
        for (int c = 0; c < 3; ++c) {
          photo.at(x, y, c) = a * data.photos[v].at(x, y, c) + (1 - a) * cabin.rgb.at(x, y, c);
        }
        matte.at(x, y) = std::max(a, cabin.rig.at(x, y));
      }
    }
    set.photos.push_back(photo);
    set.mattes.push_back(matte);
    set.truth.push_back(data.mattes[v]);
  }
  return set;
}

FloatImage Without(FloatImage matte, const FloatImage& structure) {
  if (structure.empty()) return matte;
  for (size_t i = 0; i < matte.NumPixels(); ++i) {
    if (structure.data()[i] > 0.5f) matte.data()[i] = 0.0f;
  }
  return matte;
}

// The frame and rail go; the tree, whose trunk stands at the same pixels in
// every photo of the camera ring, stays.
TEST(MatteSetTest, RigStructureGoesAndTheTreeStays) {
  const CabinPhotos set = PhotosInCabin(8);
  std::vector<Warning> warnings;
  const std::vector<FloatImage> structure =
      FindStaticStructure(set.photos, set.mattes, MatteSetOptions(), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].code, "static-structure") << warnings[0].message;
  for (size_t v = 0; v < set.photos.size(); ++v) {
    const SilhouetteScores before = CompareSilhouettes(set.mattes[v], set.truth[v]);
    const SilhouetteScores after =
        CompareSilhouettes(Without(set.mattes[v], structure[v]), set.truth[v]);
    std::printf("view %zu: IoU %.3f before, %.3f after; recall %.3f\n", v, before.iou, after.iou,
                after.recall);
    EXPECT_LT(before.iou, 0.7);
    EXPECT_GT(after.iou, 0.95);
    EXPECT_GT(after.recall, 0.97);
  }
}

// The same photo again and again is not a rig: nothing moves, nothing goes.
TEST(MatteSetTest, AStillSceneIsLeftAlone) {
  const CabinPhotos set = PhotosInCabin(1);
  const std::vector<FloatImage> photos(6, set.photos[0]), mattes(6, set.mattes[0]);
  std::vector<Warning> warnings;
  const std::vector<FloatImage> structure =
      FindStaticStructure(photos, mattes, MatteSetOptions(), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].code, "static-scene");
  for (const FloatImage& s : structure) EXPECT_TRUE(s.empty());
  // Too few photos: not tested.
  MatteSetOptions options;
  options.static_min_photos = 7;
  warnings.clear();
  FindStaticStructure(photos, mattes, options, &warnings);
  EXPECT_TRUE(warnings.empty());
}

TEST(MatteSetTest, ImplausibleMattesAreNamed) {
  const CabinPhotos set = PhotosInCabin(1);
  const FloatImage& tree = set.truth[0];
  FloatImage inverted = tree;
  for (float& a : inverted.values()) a = 1.0f - a;
  const MatteSetOptions options;
  const MatteShape shape = MeasureMatte(tree);
  EXPECT_LT(shape.border_share, 0.01);
  EXPECT_EQ(ImplausibleMatteReason(shape, shape.foreground_share, options), "");
  const MatteShape inverted_shape = MeasureMatte(inverted);
  EXPECT_GT(inverted_shape.border_share, 0.99);
  EXPECT_NE(ImplausibleMatteReason(inverted_shape, shape.foreground_share, options).find("border"),
            std::string::npos);
  // Far from the others' foreground share, without touching the border.
  MatteShape tiny = shape;
  tiny.foreground_share = shape.foreground_share / 5;
  EXPECT_NE(ImplausibleMatteReason(tiny, shape.foreground_share, options).find("median"),
            std::string::npos);
  EXPECT_EQ(ImplausibleMatteReason(tiny, 0.0, options), "") << "no set to compare with";
  // The analysis copy keeps thin structure.
  FloatImage line(9, 9, 1, 0.0f);
  for (int y = 0; y < 9; ++y) line.at(4, y) = 1.0f;
  const FloatImage small = SmallMatte(line, 3);
  EXPECT_EQ(small.width(), 3);
  EXPECT_FLOAT_EQ(small.at(1, 1), 1.0f);
  EXPECT_FLOAT_EQ(small.at(0, 1), 0.0f);
}

// A photo whose border saw a bright wall, and whose own matting took the wall
// for backdrop and the dark cloth behind the tree for foreground, is repaired
// against the cloth the other photos were keyed against: the tree alone is
// foreground against both.
TEST(MatteSetTest, RepairKeysAgainstTheSetsBackdrop) {
  SyntheticDatasetOptions synth;
  synth.seed = 2;
  synth.num_views = 1;
  synth.num_held_out = 0;
  synth.image_size = kSize;
  synth.samples_per_axis = 2;
  synth.margin = 0.3;
  const SyntheticDataset data = MakeSyntheticDataset(synth);
  const std::array<float, 3> wall = {0.8f, 0.78f, 0.7f}, cloth = {0.08f, 0.08f, 0.09f};
  FloatImage photo(kSize, kSize, 3), own(kSize, kSize, 1);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool band = x < kSize / 8 || x >= kSize - kSize / 8 || y < kSize / 8;
      const float a = data.mattes[0].at(x, y);
      for (int c = 0; c < 3; ++c) {
        photo.at(x, y, c) = a * data.photos[0].at(x, y, c) + (1 - a) * (band ? wall : cloth)[c];
      }
      own.at(x, y) = band ? a : 1.0f;  // keyed against the wall
    }
  }
  const FloatImage repaired = RepairMatte(photo, {}, own, {0.08, 0.08, 0.09}, MattingOptions());
  const double own_iou = CompareSilhouettes(own, data.mattes[0]).iou;
  const double repaired_iou = CompareSilhouettes(repaired, data.mattes[0]).iou;
  std::printf("own matte IoU %.3f, repaired %.3f\n", own_iou, repaired_iou);
  EXPECT_LT(own_iou, 0.3);
  EXPECT_GT(repaired_iou, 0.8);
  const MatteSetOptions set_options;
  const double tree_share = MeasureMatte(data.mattes[0]).foreground_share;
  EXPECT_FALSE(ImplausibleMatteReason(MeasureMatte(own), tree_share, set_options).empty());
  EXPECT_TRUE(ImplausibleMatteReason(MeasureMatte(repaired), tree_share, set_options).empty());
}

TEST(MatteSetTest, OptionsAreChecked) {
  MatteSetOptions options;
  options.static_photo_fraction = 0.4;
  try {
    options.Check();
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "MatteSet.static_photo_fraction");
  }
}

}  // namespace
}  // namespace sylva
