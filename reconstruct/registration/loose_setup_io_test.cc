#include "reconstruct/registration/loose_setup_io.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_loose_setup_io_test";
  fs::create_directories(dir);
  return dir;
}

constexpr const char* kPhotos = R"(
    "photos": [
      {"name": "front.jpg", "azimuth_deg": 0, "projection": "perspective",
       "focal_length_35mm": 28, "elevation_deg": 5},
      {"name": "side.jpg", "azimuth_deg": 90, "projection": "orthographic", "roll_deg": -2,
       "distance": 15}
    ])";

// A valid file with `extra` spliced in at the top level.
std::string File(const std::string& extra) {
  return std::string("{\"format\": \"sylva-loose-cameras\", \"version\": 1,") + kPhotos +
         (extra.empty() ? "" : ", " + extra) + "}";
}

// Parsing `json` (as file "loose.json") throws an InputError naming the file
// and containing every string of `expected`.
void ExpectError(const std::string& json, const std::vector<std::string>& expected) {
  const fs::path path = TestDir() / "loose.json";
  AtomicWriteString(path, json);
  try {
    ReadLooseSetup(path);
    FAIL() << "no error for " << json;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string()) << error.what();
    for (const std::string& text : expected) {
      EXPECT_NE(std::string(error.what()).find(text), std::string::npos)
          << "'" << text << "' not in: " << error.what();
    }
  }
}

TEST(LooseSetupIoTest, ReadsTheDocumentedExample) {
  const LooseSetup setup = ParseLooseSetup(File(R"("tree_height": 6.5, "units": "m",
    "points": [
      {"name": "base", "seen": {"front.jpg": [1510, 2950], "side.jpg": [1490, 2962]}},
      {"name": "tip1", "seen": {"front.jpg": [620.5, 1210], "side.jpg": [1700, 1190]}}
    ])"),
                                           "example.json");
  EXPECT_EQ(setup.source, "example.json");
  EXPECT_DOUBLE_EQ(setup.tree_height, 6.5);
  EXPECT_EQ(setup.units, "m");
  ASSERT_EQ(setup.photos.size(), 2u);
  const LoosePhoto& front = setup.photos[0];
  EXPECT_EQ(front.projection, LooseProjection::kPerspective);
  EXPECT_DOUBLE_EQ(front.elevation_deg, 5);
  EXPECT_DOUBLE_EQ(front.roll_deg, 0);  // default
  // 28 mm equivalent on a 4000 x 3000 photo: 28 / 36 of the longer side.
  EXPECT_NEAR(front.FocalLengthPx(4000, 3000), 28.0 / 36.0 * 4000, 1e-9);
  const LoosePhoto& side = setup.photos[1];
  EXPECT_EQ(side.projection, LooseProjection::kOrthographic);
  EXPECT_DOUBLE_EQ(side.roll_deg, -2);
  EXPECT_DOUBLE_EQ(side.distance, 15);
  EXPECT_DOUBLE_EQ(side.FocalLengthPx(4000, 3000), 0);
  ASSERT_EQ(setup.points.size(), 2u);
  EXPECT_EQ(setup.points[1].name, "tip1");
  ASSERT_NE(setup.points[1].Find(0), nullptr);
  EXPECT_DOUBLE_EQ(setup.points[1].Find(0)->point_in_image.x(), 620.5);
  EXPECT_EQ(setup.NumObservations(), 4);
}

TEST(LooseSetupIoTest, WriteThenReadGivesTheSameSetUp) {
  const LooseSetup setup = ParseLooseSetup(File(R"("tree_height": 4,
    "points": [{"name": "base", "seen": {"front.jpg": [10, 20], "side.jpg": [30, 40]}}])"),
                                           "in.json");
  const fs::path path = TestDir() / "written.json";
  WriteLooseSetup(path, setup);
  const LooseSetup read = ReadLooseSetup(path);
  ASSERT_EQ(read.photos.size(), 2u);
  EXPECT_EQ(read.photos[1].name, "side.jpg");
  EXPECT_DOUBLE_EQ(read.photos[0].focal_length_35mm, 28);
  EXPECT_DOUBLE_EQ(read.photos[1].roll_deg, -2);
  EXPECT_DOUBLE_EQ(read.tree_height, 4);
  ASSERT_EQ(read.points.size(), 1u);
  EXPECT_DOUBLE_EQ(read.points[0].Find(1)->point_in_image.y(), 40);
}

TEST(LooseSetupIoTest, RefusesBadFiles) {
  ExpectError("{\"photos\": [", {"invalid JSON"});
  ExpectError(R"({"photos": [{"name": "a.jpg", "azimuth_deg": 0, "projection": "perspective"}]})",
              {"at least 2 photos", "got 1"});
  ExpectError(File(R"("format": "sylva-cameras")"), {"/format"});
  ExpectError(R"({"version": 2, "photos": []})", {"/version", "unsupported version"});
  ExpectError(File(R"("tree_hieght": 5)"), {"unknown key 'tree_hieght'"});
  ExpectError(File(R"("tree_height": -5)"), {"/tree_height", "must be positive"});
}

TEST(LooseSetupIoTest, RefusesBadPhotos) {
  const std::string front =
      R"({"name": "front.jpg", "azimuth_deg": 0, "projection": "perspective"})";
  auto photos = [&](const std::string& second) {
    return "{\"photos\": [" + front + ", " + second + "]}";
  };
  ExpectError(photos(R"({"name": "front.jpg", "azimuth_deg": 90, "projection": "perspective"})"),
              {"photo 'front.jpg' is listed twice"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": "east", "projection": "perspective"})"),
              {"/photos/1/azimuth_deg", "expected a number"});
  ExpectError(photos(R"({"name": "side.jpg", "projection": "perspective"})"),
              {"/photos/1", "missing key 'azimuth_deg'"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90})"), {"missing key 'projection'"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "projection": "fisheye"})"),
              {"/photos/1/projection", "'fisheye'"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "elevation_deg": 95,
                         "projection": "perspective"})"),
              {"photo 'side.jpg'", "elevation_deg must be in (-90, 90)"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "roll_deg": 200,
                         "projection": "perspective"})"),
              {"photo 'side.jpg'", "roll_deg"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "projection": "perspective",
                         "focal_length_px": -3})"),
              {"/photos/1/focal_length_px", "must be positive"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "projection": "perspective",
                         "focal_length_px": 3000, "focal_length_35mm": 28})"),
              {"photo 'side.jpg'", "not both"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "projection": "orthographic",
                         "focal_length_px": 3000})"),
              {"photo 'side.jpg'", "orthographic photo has no focal length"});
  ExpectError(photos(R"({"name": "", "azimuth_deg": 90, "projection": "orthographic"})"),
              {"/photos/1/name", "must not be empty"});
  ExpectError(photos(R"({"name": "side.jpg", "azimuth_deg": 90, "projection": "orthographic",
                         "azimuth": 80})"),
              {"/photos/1", "unknown key 'azimuth'"});
}

TEST(LooseSetupIoTest, RefusesBadPoints) {
  ExpectError(
      File(R"("points": [
      {"name": "base", "seen": {"front.jpg": [1, 2], "back.jpg": [3, 4]}}])"),
      {"/points/0/seen/back.jpg", "point 'base'", "photo 'back.jpg'", "not among the photos"});
  ExpectError(File(R"("points": [{"name": "base", "seen": {"front.jpg": [1, 2]}}])"),
              {"point 'base'", "seen in 1 photo", "at least 2"});
  ExpectError(File(R"("points": [
      {"name": "tip", "seen": {"front.jpg": [1, 2], "side.jpg": [3, 4]}}])"),
              {"must include 'base'"});
  ExpectError(File(R"("points": [
      {"name": "base", "seen": {"front.jpg": [1, 2], "side.jpg": [3, 4]}},
      {"name": "base", "seen": {"front.jpg": [1, 2], "side.jpg": [3, 4]}}])"),
              {"point 'base' is listed twice"});
  ExpectError(File(R"("points": [
      {"name": "base", "seen": {"front.jpg": [1, 2], "side.jpg": [-3, 4]}}])"),
              {"point 'base' in photo 'side.jpg'", "non-negative"});
  ExpectError(File(R"("points": [
      {"name": "base", "seen": {"front.jpg": [1, 2, 3], "side.jpg": [3, 4]}}])"),
              {"/points/0/seen/front.jpg", "expected 2 numbers"});
  ExpectError(File(R"("points": [
      {"name": "base", "seen": {"front.jpg": [1, "x"], "side.jpg": [3, 4]}}])"),
              {"/points/0/seen/front.jpg/1", "expected a number"});
  ExpectError(File(R"("points": [{"name": "base", "seen": [[1, 2], [3, 4]]}])"),
              {"/points/0/seen", "expected an object"});
}

}  // namespace
}  // namespace sylva
