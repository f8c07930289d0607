#include "reconstruct/attractors/livewire_target.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr int kWidth = 100, kHeight = 80;

// One pinhole view at the origin looking down +Z (focal length 100 px, the
// principal point at the image centre (50, 40)).
ImageSet OneView() {
  ImageSet views;
  views.cameras[1] = Camera::Pinhole(kWidth, kHeight, 100.0);
  View view;
  view.image_id = 1;
  view.name = "a.png";
  view.camera_id = 1;
  views.views.push_back(view);
  return views;
}

// Foreground in the block x in [40, 60), y in [20, 60).
FloatImage BlockMatte() {
  FloatImage matte(kWidth, kHeight, 1, 0.0f);
  for (int y = 20; y < 60; ++y) {
    for (int x = 40; x < 60; ++x) matte.at(x, y) = 1.0f;
  }
  return matte;
}

TEST(LivewireTargetTest, BaseInFrameIsTheTarget) {
  const LivewireTarget target =
      ChooseLivewireTarget(OneView(), 0, Eigen::Vector3d(0.5, 1.0, 5.0), BlockMatte(), 0.5);
  ASSERT_TRUE(target.found);
  EXPECT_NEAR(target.point_in_image.x(), 60.0, 1e-9);
  EXPECT_NEAR(target.point_in_image.y(), 60.0, 1e-9);
  EXPECT_EQ(target.note, "");
}

TEST(LivewireTargetTest, BaseOutOfFrameMovesToTheMattesNearestPixel) {
  // Projects to (52.2, 240), below the image: the nearest foreground pixel
  // is (52, 59), the block's bottom row.
  const LivewireTarget target =
      ChooseLivewireTarget(OneView(), 0, Eigen::Vector3d(0.11, 10.0, 5.0), BlockMatte(), 0.5);
  ASSERT_TRUE(target.found);
  EXPECT_NEAR(target.point_in_image.x(), 52.5, 1e-12);
  EXPECT_NEAR(target.point_in_image.y(), 59.5, 1e-12);
  EXPECT_NE(target.note.find("outside the photo"), std::string::npos) << target.note;
  // Without foreground there is nowhere to end the paths.
  EXPECT_THROW(ChooseLivewireTarget(OneView(), 0, Eigen::Vector3d(0.11, 10.0, 5.0),
                                    FloatImage(kWidth, kHeight, 1, 0.0f), 0.5),
               InputError);
}

TEST(LivewireTargetTest, BaseBehindTheCameraHasNoTarget) {
  const LivewireTarget target =
      ChooseLivewireTarget(OneView(), 0, Eigen::Vector3d(0.0, 0.0, -5.0), BlockMatte(), 0.5);
  EXPECT_FALSE(target.found);
  EXPECT_EQ(target.note, "tree base behind the camera");
}

}  // namespace
}  // namespace sylva
