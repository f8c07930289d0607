#include "core/io/camera_file.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_camera_file_test";
  fs::create_directories(dir);
  return dir;
}

void ExpectInputErrorContaining(const std::string& json, const std::string& expected) {
  const fs::path path = TestDir() / "bad.json";
  AtomicWriteString(path, json);
  try {
    ReadCameraFile(path);
    FAIL() << "no error for " << json;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string());
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
  }
}

TEST(CameraFileTest, TwoOrthographicViewsAtRightAngles) {
  const fs::path path = TestDir() / "ortho.json";
  AtomicWriteString(path, R"({
    "format": "sylva-cameras", "version": 1, "units": "m",
    "cameras": [{"camera_id": 1, "model": "ORTHOGRAPHIC", "width": 200, "height": 100,
                 "params": [10, 10, 100, 50]}],
    "images": [
      {"image_id": 2, "name": "side.png", "camera_id": 1,
       "look_at": {"center": [5, 0, 1], "target": [0, 0, 1], "up": [0, 0, 1]}},
      {"image_id": 1, "name": "front.png", "camera_id": 1,
       "look_at": {"center": [0, -5, 1], "target": [0, 0, 1]}}
    ]})");
  std::string units;
  const ImageSet set = ReadCameraFile(path, &units);
  EXPECT_EQ(units, "m");
  ASSERT_EQ(set.NumViews(), 2);
  EXPECT_EQ(set.views[0].name, "front.png");  // sorted by id
  // Front view looks along +y; world +z is up in the image (smaller row).
  EXPECT_TRUE(set.views[0].ViewingDirection().isApprox(Eigen::Vector3d::UnitY()));
  Eigen::Vector2d low, high;
  ASSERT_TRUE(set.Project(0, Eigen::Vector3d(0, 0, 0), &low));
  ASSERT_TRUE(set.Project(0, Eigen::Vector3d(0, 0, 2), &high));
  EXPECT_NEAR(low.x(), 100, 1e-9);
  EXPECT_NEAR(low.y() - high.y(), 20, 1e-9);
  // Side view at right angles: world +y maps to image x.
  EXPECT_NEAR(set.views[0].ViewingDirection().dot(set.views[1].ViewingDirection()), 0, 1e-12);

  // Write and read back.
  const fs::path copy = TestDir() / "copy.json";
  WriteCameraFile(copy, set, "m");
  const ImageSet again = ReadCameraFile(copy);
  ASSERT_EQ(again.NumViews(), 2);
  for (int v = 0; v < 2; ++v) {
    Eigen::Vector2d a, b;
    const Eigen::Vector3d point(0.3, -0.2, 1.7);
    ASSERT_TRUE(set.Project(v, point, &a));
    ASSERT_TRUE(again.Project(v, point, &b));
    EXPECT_LT((a - b).norm(), 1e-9);
  }
}

TEST(CameraFileTest, ErrorsNameFileAndLocation) {
  ExpectInputErrorContaining("{ not json", "invalid JSON");
  ExpectInputErrorContaining(R"({"format": "other", "version": 1})", "/format");
  ExpectInputErrorContaining(
      R"({"format": "sylva-cameras", "version": 1, "cameras": [{"camera_id": 1,
          "model": "PINHOLE", "width": 10, "height": 10, "params": [1, 1, 5]}], "images": []})",
      "needs 4 parameters");
  ExpectInputErrorContaining(
      R"({"format": "sylva-cameras", "version": 1, "cameras": [{"camera_id": 1,
          "model": "PINHOLE", "width": "ten", "height": 10, "params": [1, 1, 5, 5]}],
          "images": []})",
      "/cameras/0/width: expected an integer");
  ExpectInputErrorContaining(
      R"({"format": "sylva-cameras", "version": 1, "cameras": [{"camera_id": 1,
          "model": "PINHOLE", "width": 10, "height": 10, "params": [1, 1, 5, 5]}],
          "images": [{"image_id": 1, "name": "a.png", "camera_id": 2,
                      "cam_from_world": {"qvec": [1, 0, 0, 0], "tvec": [0, 0, 0]}}]})",
      "refers to camera 2");
  ExpectInputErrorContaining(
      R"({"format": "sylva-cameras", "version": 1, "cameras": [], "images": [
          {"image_id": 1, "name": "a.png", "camera_id": 1}]})",
      "needs 'cam_from_world' or 'look_at'");
}

}  // namespace
}  // namespace sylva
