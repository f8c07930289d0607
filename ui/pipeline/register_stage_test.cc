// The register stage's steps on cameras built in code (no photos, no COLMAP).
#include "ui/pipeline/register_stage.h"

#include <gtest/gtest.h>

#include "core/io/camera_file.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "sylva_register_stage_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Registration TwoViews(const Camera& camera) {
  Registration registration;
  registration.cameras.cameras[1] = camera;
  for (int i = 0; i < 2; ++i) {
    View view;
    view.image_id = i + 1;
    view.name = "view_" + std::to_string(i) + ".png";
    view.camera_id = 1;
    view.cam_from_world.translation = Eigen::Vector3d(0.0, 0.0, 3.0 + i);
    registration.cameras.views.push_back(view);
  }
  registration.unregistered = {"lost.png"};
  registration.units = "mm";
  registration.details["method"] = "given";
  return registration;
}

TEST(RegisterStageTest, HeldOutPhotosWithoutCamerasAreNamedThenAllCounted) {
  const std::vector<Warning> warnings =
      UnregisteredWarnings({"a.png", "held.png"}, {"held.png", "other.png"}, 10);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].code, "held-out-unregistered");
  EXPECT_EQ(warnings[0].subject, "held.png");
  EXPECT_EQ(warnings[1].code, "unregistered-photos");
  EXPECT_NE(warnings[1].message.find("2 of 10 photos not registered (first: a.png)"),
            std::string::npos)
      << warnings[1].message;
  EXPECT_TRUE(UnregisteredWarnings({}, {"held.png"}, 10).empty());
}

TEST(RegisterStageTest, PinholeCamerasAreAlsoWrittenAsAColmapModel) {
  const fs::path dir = TestDir("pinhole");
  const std::vector<fs::path> written =
      WriteRegistration(TwoViews(Camera::Pinhole(64, 48, 50.0)), dir);
  EXPECT_EQ(written.size(), 6u);
  for (const fs::path& file : written) EXPECT_TRUE(fs::is_regular_file(file)) << file;
  std::string units;
  const ImageSet cameras = ReadCameraFile(dir / "cameras.json", &units);
  EXPECT_EQ(cameras.NumViews(), 2);
  EXPECT_EQ(units, "mm");
  EXPECT_EQ(ReadFileToString(dir / "unregistered.txt"), "lost.png\n");
  const Json details = ReadJsonFile(dir / "registration.json");
  EXPECT_EQ(details["registered"], 2);
  EXPECT_EQ(details["method"], "given");
  EXPECT_EQ(details["colmap_model"], "out/cameras/colmap/");
}

TEST(RegisterStageTest, OrthographicCamerasHaveNoColmapModel) {
  const fs::path dir = TestDir("orthographic");
  fs::create_directories(dir / "colmap");  // from an earlier run
  const std::vector<fs::path> written =
      WriteRegistration(TwoViews(Camera::Orthographic(64, 48, 10.0)), dir);
  EXPECT_EQ(written.size(), 3u);
  EXPECT_FALSE(fs::exists(dir / "colmap"));
  EXPECT_EQ(ReadJsonFile(dir / "registration.json")["colmap_model"], "");
  EXPECT_EQ(ReadCameraFile(dir / "cameras.json").NumViews(), 2);
}

}  // namespace
}  // namespace sylva
