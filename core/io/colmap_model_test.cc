#include "core/io/colmap_model.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"

namespace sylva {
namespace {

const fs::path kRomiDir = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "romi-colmap";

// A fresh scratch folder per test.
fs::path TestDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "sylva_colmap_model_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void ExpectSameCameras(const ImageSet& a, const ImageSet& b, double tolerance) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [camera_id, camera] : a.cameras) {
    ASSERT_EQ(b.cameras.count(camera_id), 1u) << camera_id;
    const Camera& other = b.cameras.at(camera_id);
    EXPECT_EQ(camera.model(), other.model());
    EXPECT_EQ(camera.width(), other.width());
    EXPECT_EQ(camera.height(), other.height());
    ASSERT_EQ(camera.params().size(), other.params().size());
    for (size_t i = 0; i < camera.params().size(); ++i) {
      EXPECT_NEAR(camera.params()[i], other.params()[i], tolerance) << camera_id << " " << i;
    }
  }
}

void ExpectSameViews(const ImageSet& a, const ImageSet& b, double tolerance) {
  ASSERT_EQ(a.NumViews(), b.NumViews());
  for (int i = 0; i < a.NumViews(); ++i) {
    const View& view = a.views[i];
    const View& other = b.views[i];
    EXPECT_EQ(view.image_id, other.image_id);
    EXPECT_EQ(view.name, other.name);
    EXPECT_EQ(view.camera_id, other.camera_id);
    EXPECT_LT((view.cam_from_world.rotation.coeffs() - other.cam_from_world.rotation.coeffs())
                  .cwiseAbs()
                  .maxCoeff(),
              tolerance)
        << view.name;
    EXPECT_LT(
        (view.cam_from_world.translation - other.cam_from_world.translation).cwiseAbs().maxCoeff(),
        tolerance * (1 + view.cam_from_world.translation.norm()))
        << view.name;
  }
}

void ExpectSamePoints(const ImageSet& a, const ImageSet& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].point3d_id, b.points[i].point3d_id);
    EXPECT_EQ(a.points[i].position, b.points[i].position);
    EXPECT_EQ(a.points[i].color, b.points[i].color);
    EXPECT_EQ(a.points[i].error, b.points[i].error);
  }
}

// Reading `model_dir` must throw InputError whose source is `source` and whose
// message contains `expected`.
void ExpectReadError(const fs::path& model_dir, const std::string& source,
                     const std::string& expected) {
  try {
    ReadColmapModel(model_dir);
    ADD_FAILURE() << "no error, expected " << source << ": " << expected;
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), source) << error.what();
    EXPECT_NE(error.message().find(expected), std::string::npos) << error.what();
  }
}

// ---------------------------------------------------------------------------
// The ROMI model, converted to binary by COLMAP 3.8 itself.

TEST(ColmapModelTest, RomiTextAndBinaryAgree) {
  ASSERT_TRUE(IsColmapModelDir(kRomiDir / "text"));
  ASSERT_TRUE(IsColmapModelDir(kRomiDir / "bin"));
  EXPECT_FALSE(IsColmapModelDir(kRomiDir));
  const ImageSet text = ReadColmapModel(kRomiDir / "text");
  const ImageSet binary = ReadColmapModel(kRomiDir / "bin");
  ASSERT_EQ(text.NumViews(), 72);
  ASSERT_EQ(text.cameras.size(), 1u);
  const Camera& camera = text.cameras.at(1);
  EXPECT_EQ(camera.model(), CameraModel::kOpenCV);
  EXPECT_EQ(camera.width(), 1616);
  EXPECT_EQ(camera.height(), 1080);
  EXPECT_EQ(camera.params()[0], 1129.7998905434683);
  EXPECT_EQ(camera.params()[4], -0.0076897833957798355);
  EXPECT_EQ(text.views[0].image_id, 1);
  EXPECT_EQ(text.views[0].name, "pict20190201_110110_0.jpg");
  EXPECT_TRUE(text.points.empty());
  ExpectSameCameras(text, binary, 1e-12);
  ExpectSameViews(text, binary, 1e-12);
  ExpectSamePoints(text, binary);
}

// PROVENANCE.md: the stem point (378, 420, 250) mm projects in held-out
// images (IMAGE_ID) 2, 26 and 50 at these pixels, computed by the dataset's
// own Python reader and OPENCV projection (rounded to 0.1 px).
TEST(ColmapModelTest, RomiStemPointProjectsAsVerified) {
  const Eigen::Vector3d stem_point_in_world(378, 420, 250);
  const std::vector<std::pair<int, Eigen::Vector2d>> expected = {
      {2, {893.8, 845.5}}, {26, {872.3, 748.4}}, {50, {770.9, 799.8}}};
  for (const char* form : {"text", "bin"}) {
    const ImageSet image_set = ReadColmapModel(kRomiDir / form);
    for (const auto& [image_id, expected_in_image] : expected) {
      int view_idx = -1;
      for (int i = 0; i < image_set.NumViews(); ++i) {
        if (image_set.views[i].image_id == image_id) view_idx = i;
      }
      ASSERT_GE(view_idx, 0) << image_id;
      Eigen::Vector2d point_in_image;
      ASSERT_TRUE(image_set.Project(view_idx, stem_point_in_world, &point_in_image));
      EXPECT_NEAR(point_in_image.x(), expected_in_image.x(), 0.1) << form << " " << image_id;
      EXPECT_NEAR(point_in_image.y(), expected_in_image.y(), 0.1) << form << " " << image_id;
    }
  }
}

// Our binary writer reproduces COLMAP's bytes where COLMAP's output order is
// defined (one camera; no points).
TEST(ColmapModelTest, BinaryWriterMatchesColmapBytes) {
  const fs::path dir = TestDir("colmap_bytes");
  WriteColmapModelBinary(ReadColmapModel(kRomiDir / "text"), dir);
  EXPECT_EQ(ReadFileToString(dir / "cameras.bin"),
            ReadFileToString(kRomiDir / "bin" / "cameras.bin"));
  EXPECT_EQ(ReadFileToString(dir / "points3D.bin"),
            ReadFileToString(kRomiDir / "bin" / "points3D.bin"));
  EXPECT_EQ(fs::file_size(dir / "images.bin"), fs::file_size(kRomiDir / "bin" / "images.bin"));
}

// ---------------------------------------------------------------------------
// Round trips.

// One camera per COLMAP model, views with random poses, points.
ImageSet RandomModel(uint64_t seed) {
  RandomEngine rng(seed);
  ImageSet image_set;
  image_set.cameras.emplace(3, Camera(CameraModel::kSimplePinhole, 640, 480,
                                      {rng.Uniform(400, 600), 320.5, rng.Uniform(200, 280)}));
  image_set.cameras.emplace(
      7, Camera(CameraModel::kPinhole, 1000, 700, {rng.Uniform(800, 900), 810.25, 500.1, 350.3}));
  image_set.cameras.emplace(8, Camera(CameraModel::kSimpleRadial, 300, 200,
                                      {rng.Uniform(200, 300), 150, 100, -1e-3 * rng.Uniform()}));
  image_set.cameras.emplace(
      10, Camera(CameraModel::kRadial, 300, 200, {250, 150, 100, rng.Normal(), rng.Normal()}));
  image_set.cameras.emplace(
      11, Camera(CameraModel::kOpenCV, 1616, 1080,
                 {1e3 / 3, 1e3 / 7, 808, 540, rng.Normal(), rng.Normal(), 1e-20, -1e300}));
  const std::vector<int> camera_ids = {3, 7, 8, 10, 11};
  for (int i = 0; i < 12; ++i) {
    View view;
    view.image_id = 5 * i + (i % 3);  // sorted, not contiguous
    view.name = "dir/photo_" + std::to_string(i) + ".jpg";
    view.camera_id = camera_ids[i % camera_ids.size()];
    const Eigen::Quaterniond rotation(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal());
    view.cam_from_world = Rigid3d(
        rotation, Eigen::Vector3d(rng.Normal(0, 100), rng.Normal(), rng.Uniform(-1e-9, 1e9)));
    image_set.views.push_back(view);
  }
  for (int i = 0; i < 20; ++i) {
    Point3D point;
    point.point3d_id = (int64_t{1} << 40) + 3 * i;
    point.position = Eigen::Vector3d(rng.Normal(), rng.Normal(0, 1e5), rng.Uniform());
    point.color = Eigen::Vector3i(i, 255 - i, static_cast<int>(rng.UniformInt(256)));
    point.error = rng.Uniform();
    image_set.points.push_back(point);
  }
  return image_set;
}

TEST(ColmapModelTest, RoundTripsEveryPinholeModel) {
  const ImageSet original = RandomModel(42);
  const fs::path text_dir = TestDir("round_trip_text");
  const fs::path binary_dir = TestDir("round_trip_bin");
  WriteColmapModelText(original, text_dir);
  WriteColmapModelBinary(original, binary_dir);
  for (const fs::path& dir : {text_dir, binary_dir}) {
    const ImageSet read = ReadColmapModel(dir);
    ExpectSameCameras(original, read, 0.0);  // parameters are exact
    ExpectSameViews(original, read, 1e-15);  // poses are renormalized
    ExpectSamePoints(original, read);
  }
  // Text and binary forms of the same model agree, and both can be rewritten.
  const ImageSet from_text = ReadColmapModelText(text_dir);
  WriteColmapModelBinary(from_text, text_dir);
  ExpectSameViews(from_text, ReadColmapModelBinary(text_dir), 1e-15);
  ExpectSameCameras(from_text, ReadColmapModel(text_dir), 0.0);
}

TEST(ColmapModelTest, WriteLeavesNoTemporaryFiles) {
  const fs::path dir = TestDir("no_temp");
  WriteColmapModelText(RandomModel(1), dir / "model");
  WriteColmapModelBinary(RandomModel(1), dir / "model");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir / "model")) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"cameras.bin", "cameras.txt", "images.bin",
                                             "images.txt", "points3D.bin", "points3D.txt"}));
}

// ---------------------------------------------------------------------------
// Text parsing.

void WriteText(const fs::path& dir, const std::string& cameras, const std::string& images,
               const std::string& points = "") {
  AtomicWriteString(dir / "cameras.txt", cameras);
  AtomicWriteString(dir / "images.txt", images);
  if (!points.empty()) AtomicWriteString(dir / "points3D.txt", points);
}

constexpr char kTwoCameras[] =
    "# Camera list\n"
    "1 PINHOLE 100 80 90 91 50 40\n"
    "\n"
    "2 SIMPLE_RADIAL 200 100 150 100 50 0.01\r\n";

TEST(ColmapModelTest, SkipsPoints2DObservationsAndParsesTracks) {
  const fs::path dir = TestDir("observations");
  WriteText(dir, kTwoCameras,
            "# Image list with two lines of data per image:\n"
            "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
            "9 1 0 0 0 0.5 -1 2 2 b.jpg\n"
            "12.5 30.25 -1 40 41.5 7 0.1 0.2 12\n"
            "\n"
            "# a comment between images\n"
            "4 0 0 0 2 1 2 3 1 a.jpg\n"
            "\n"
            "6 0.5 0.5 0.5 0.5 0 0 0 1 c.jpg\n"
            "1 2 3",  // last POINTS2D line without a newline
            "# 3D point list\n"
            "12 1.5 2.5 -3.5 255 0 128 0.75 9 1 4 0\n"
            "7 0 0 1 1 2 3 -1\n");
  const ImageSet image_set = ReadColmapModel(dir);
  ASSERT_EQ(image_set.NumViews(), 3);
  EXPECT_EQ(image_set.views[0].name, "a.jpg");  // sorted by IMAGE_ID
  EXPECT_EQ(image_set.views[1].name, "c.jpg");
  EXPECT_EQ(image_set.views[2].name, "b.jpg");
  EXPECT_EQ(image_set.views[2].camera_id, 2);
  EXPECT_EQ(image_set.views[2].cam_from_world.translation, Eigen::Vector3d(0.5, -1, 2));
  // QW QX QY QZ = (0, 0, 0, 2): a half turn about z, after normalization.
  const Eigen::Vector3d x_in_cam =
      image_set.views[0].cam_from_world.rotation * Eigen::Vector3d::UnitX();
  EXPECT_LT((x_in_cam + Eigen::Vector3d::UnitX()).norm(), 1e-15);
  EXPECT_EQ(image_set.cameras.at(2).params()[3], 0.01);  // '\r' ignored
  ASSERT_EQ(image_set.points.size(), 2u);
  EXPECT_EQ(image_set.points[0].point3d_id, 7);  // sorted by POINT3D_ID
  EXPECT_EQ(image_set.points[0].error, -1);
  EXPECT_EQ(image_set.points[1].position, Eigen::Vector3d(1.5, 2.5, -3.5));
  EXPECT_EQ(image_set.points[1].color, Eigen::Vector3i(255, 0, 128));
  EXPECT_EQ(image_set.points[1].error, 0.75);
}

// Writes cameras.txt and images.txt (one image per camera line) and expects
// the error at `file`:`line`.
void ExpectTextError(const std::string& cameras, const std::string& images,
                     const std::string& points, const std::string& file, int line,
                     const std::string& expected) {
  const fs::path dir = TestDir("text_error");
  WriteText(dir, cameras, images, points);
  ExpectReadError(dir, (dir / file).string() + ":" + std::to_string(line), expected);
}

TEST(ColmapModelTest, TextErrorsNameFileAndLine) {
  const std::string image = "1 1 0 0 0 0 0 0 1 a.jpg\n\n";
  const std::string camera = "1 PINHOLE 100 80 90 91 50 40\n";
  ExpectTextError("#\n1 FISHEYE 100 80 90 50 40\n", image, "", "cameras.txt", 2,
                  "unsupported camera model 'FISHEYE'");
  ExpectTextError("1 ORTHOGRAPHIC 100 80 90 90 50 40\n", image, "", "cameras.txt", 1,
                  "ORTHOGRAPHIC");
  ExpectTextError("1 PINHOLE 100 80 90 91 50\n", image, "", "cameras.txt", 1,
                  "needs 4 parameters, got 3");
  ExpectTextError("1 PINHOLE 100 eighty 90 91 50 40\n", image, "", "cameras.txt", 1,
                  "HEIGHT must be an integer, got 'eighty'");
  ExpectTextError("1 PINHOLE 100 80 90 nan 50 40\n", image, "", "cameras.txt", 1,
                  "PARAMS must be a finite number, got 'nan'");
  ExpectTextError("1 PINHOLE 100 80 -90 91 50 40\n", image, "", "cameras.txt", 1,
                  "focal lengths must be positive");
  ExpectTextError("1 PINHOLE\n", image, "", "cameras.txt", 1, "got 2 fields");
  ExpectTextError(std::string("1 PINHOLE 100 80 90 91 50 4\0\n", 29), image, "", "cameras.txt", 1,
                  "PARAMS must be a finite number, got '4\\x00'");
  ExpectTextError(camera + "\n" + camera, image, "", "cameras.txt", 3, "duplicate CAMERA_ID 1");
  ExpectTextError("-1 PINHOLE 100 80 90 91 50 40\n", image, "", "cameras.txt", 1,
                  "CAMERA_ID must be in [0, 2147483647], got -1");

  ExpectTextError(camera, "#\n#\n1 1 0 zero 0 0 0 0 1 a.jpg\n\n", "", "images.txt", 3,
                  "QY must be a finite number, got 'zero'");
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 2 a.jpg\n\n", "", "images.txt", 1,
                  "CAMERA_ID 2 is not in the cameras file");
  ExpectTextError(camera, "1 0 0 0 0 0 0 0 1 a.jpg\n\n", "", "images.txt", 1, "zero length");
  ExpectTextError(camera, image + "1 1 0 0 0 0 0 0 1 b.jpg\n\n", "", "images.txt", 3,
                  "duplicate IMAGE_ID 1");
  ExpectTextError(camera, image + "2 1 0 0 0 0 0 0 1 a.jpg\n\n", "", "images.txt", 3,
                  "duplicate image NAME 'a.jpg'");
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 1 my photo.jpg\n\n", "", "images.txt", 1,
                  "names with spaces");
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 1\n\n", "", "images.txt", 1, "got 9 fields");
  // One line per image: the second image line is taken as POINTS2D, as COLMAP would.
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 1 a.jpg\n2 1 0 0 0 0 0 0 1 b.jpg\n", "", "images.txt", 2,
                  "two lines per image");
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 1 a.jpg\n1 2 x\n", "", "images.txt", 2,
                  "POINTS2D POINT3D_ID must be an integer, got 'x'");
  ExpectTextError(camera, "1 1 0 0 0 0 0 0 1 a.jpg\n1 2 -2\n", "", "images.txt", 2,
                  "POINTS2D POINT3D_ID must be in [-1");

  ExpectTextError(camera, image, "#\n1 0 0 0 256 0 0 0\n", "points3D.txt", 2,
                  "R must be in [0, 255], got 256");
  ExpectTextError(camera, image, "1 0 0 0 1 2 3 0.5 1\n", "points3D.txt", 1, "got 9 fields");
  ExpectTextError(camera, image, "1 0 0 0 1 2 3 0.5 1 x\n", "points3D.txt", 1,
                  "TRACK POINT2D_IDX must be an integer");
  ExpectTextError(camera, image, "1 0 0 0 1 2 3 0\n1 0 0 0 1 2 3 0\n", "points3D.txt", 2,
                  "duplicate POINT3D_ID 1");
  ExpectTextError(camera, image, "1 0 inf 0 1 2 3 0\n", "points3D.txt", 1,
                  "Y must be a finite number");
  ExpectTextError(camera, image, "99999999999999999999 0 0 0 1 2 3 0\n", "points3D.txt", 1,
                  "POINT3D_ID must be in");
}

TEST(ColmapModelTest, MissingFilesAreNamed) {
  const fs::path dir = TestDir("missing");
  ExpectReadError(dir, (dir / "cameras.txt").string(), "no such file");
  AtomicWriteString(dir / "cameras.txt", "1 PINHOLE 100 80 90 91 50 40\n");
  ExpectReadError(dir, (dir / "images.txt").string(), "no such file");
  AtomicWriteString(dir / "images.txt", "# no images\n");
  ExpectReadError(dir, (dir / "images.txt").string(), "no images");
  AtomicWriteString(dir / "cameras.bin", std::string(8, '\0'));
  ExpectReadError(dir, (dir / "images.bin").string(), "no such file");
}

// ---------------------------------------------------------------------------
// Binary parsing.

// Little-endian record bytes for hand-made binary files.
class Bytes {
 public:
  Bytes& U32(uint32_t value) { return Append(value, 4); }
  Bytes& U64(uint64_t value) { return Append(value, 8); }
  Bytes& F64(double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    return Append(bits, 8);
  }
  Bytes& Text(const std::string& text) {
    bytes_.append(text.c_str(), text.size() + 1);
    return *this;
  }
  const std::string& str() const { return bytes_; }

 private:
  Bytes& Append(uint64_t value, int num_bytes) {
    for (int i = 0; i < num_bytes; ++i) bytes_.push_back(static_cast<char>(value >> (8 * i)));
    return *this;
  }
  std::string bytes_;
};

Bytes PinholeCameraRecord(uint32_t camera_id, uint32_t model_id = 1) {
  Bytes bytes;
  bytes.U32(camera_id).U32(model_id).U64(100).U64(80).F64(90).F64(91).F64(50).F64(40);
  return bytes;
}

Bytes IdentityImageRecord(uint32_t image_id, uint32_t camera_id, const std::string& name) {
  Bytes bytes;
  bytes.U32(image_id).F64(1).F64(0).F64(0).F64(0).F64(0).F64(0).F64(0).U32(camera_id).Text(name);
  return bytes;
}

void ExpectBinaryError(const std::string& cameras, const std::string& images,
                       const std::string& file, const std::string& expected) {
  const fs::path dir = TestDir("binary_error");
  AtomicWriteString(dir / "cameras.bin", cameras);
  AtomicWriteString(dir / "images.bin", images);
  ExpectReadError(dir, (dir / file).string(), expected);
}

TEST(ColmapModelTest, BinaryErrorsNameFile) {
  const std::string camera = Bytes().U64(1).str() + PinholeCameraRecord(1).str();
  const std::string image =
      Bytes().U64(1).str() + IdentityImageRecord(1, 1, "a.jpg").str() + Bytes().U64(0).str();
  // Sanity: the hand-made model reads.
  {
    const fs::path dir = TestDir("binary_ok");
    AtomicWriteString(dir / "cameras.bin", camera);
    AtomicWriteString(dir / "images.bin", image);
    EXPECT_EQ(ReadColmapModel(dir).views.at(0).name, "a.jpg");
  }
  ExpectBinaryError(Bytes().U64(1).str() + PinholeCameraRecord(1, 99).str(), image, "cameras.bin",
                    "camera #0: unsupported COLMAP camera model id 99");
  ExpectBinaryError(Bytes().U64(1).str() + PinholeCameraRecord(1, 5).str(), image, "cameras.bin",
                    "unsupported COLMAP camera model id 5");
  ExpectBinaryError(
      Bytes().U64(2).str() + PinholeCameraRecord(1).str() + PinholeCameraRecord(1).str(), image,
      "cameras.bin", "camera #1: duplicate CAMERA_ID 1");
  ExpectBinaryError(Bytes().U64(uint64_t{1} << 60).str() + PinholeCameraRecord(1).str(), image,
                    "cameras.bin", "number of cameras is 1152921504606846976");
  ExpectBinaryError(camera + "x", image, "cameras.bin", "1 unexpected bytes");
  ExpectBinaryError(camera.substr(0, camera.size() - 3), image, "cameras.bin", "file is truncated");
  ExpectBinaryError(
      camera,
      Bytes().U64(1).str() + IdentityImageRecord(1, 2, "a.jpg").str() + Bytes().U64(0).str(),
      "images.bin", "image #0: CAMERA_ID 2 is not in the cameras file");
  ExpectBinaryError(camera,
                    Bytes().U64(1).str() + IdentityImageRecord(0x80000000u, 1, "a.jpg").str() +
                        Bytes().U64(0).str(),
                    "images.bin", "IMAGE_ID 2147483648 is too large");
  ExpectBinaryError(camera,
                    Bytes().U64(1).str() + IdentityImageRecord(1, 1, "a.jpg").str() +
                        Bytes().U64(uint64_t{1} << 62).str(),
                    "images.bin", "number of 2D points is");
  const std::string unterminated_name = IdentityImageRecord(1, 1, "").str();
  ExpectBinaryError(
      camera,
      Bytes().U64(1).str() + unterminated_name.substr(0, unterminated_name.size() - 1) +
          "a_long_name_without_its_nul.jpg",
      "images.bin", "image #0: file is truncated: NAME at offset 72 has no terminating NUL");
}

// Every truncation of COLMAP's own files, and random byte corruptions, give
// an InputError naming the file (or read successfully), never a crash.
TEST(ColmapModelTest, DamagedBinaryFilesGiveInputErrors) {
  const fs::path dir = TestDir("damaged");
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    fs::copy_file(kRomiDir / "bin" / name, dir / name);
  }
  RandomEngine rng(7);
  for (const char* name : {"cameras.bin", "images.bin"}) {
    const std::string original = ReadFileToString(kRomiDir / "bin" / name);
    const std::string source = (dir / name).string();
    for (size_t size = 0; size < original.size(); size += (size < 200 ? 1 : 37)) {
      AtomicWriteString(dir / name, original.substr(0, size));
      ExpectReadError(dir, source, "");
    }
    for (int trial = 0; trial < 300; ++trial) {
      std::string damaged = original;
      for (int k = 0; k < 3; ++k) {
        damaged[rng.UniformInt(static_cast<uint32_t>(damaged.size()))] =
            static_cast<char>(rng.UniformInt(256));
      }
      AtomicWriteString(dir / name, damaged);
      try {
        ReadColmapModel(dir);
      } catch (const InputError& error) {
        // A damaged camera id is reported where the images refer to it.
        EXPECT_TRUE(error.source() == source || error.source() == (dir / "images.bin").string())
            << error.what();
      }
    }
    AtomicWriteString(dir / name, original);
  }
  EXPECT_EQ(ReadColmapModel(dir).NumViews(), 72);
}

// ---------------------------------------------------------------------------
// What COLMAP cannot hold.

TEST(ColmapModelTest, WritersRejectWhatColmapCannotHold) {
  ImageSet image_set = RandomModel(3);
  image_set.cameras.emplace(20, Camera::Orthographic(100, 100, 2.0));
  image_set.views[0].camera_id = 20;
  const fs::path dir = TestDir("orthographic");
  try {
    WriteColmapModelText(image_set, dir);
    ADD_FAILURE() << "ORTHOGRAPHIC written as text";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), (dir / "cameras.txt").string());
    EXPECT_NE(error.message().find("ORTHOGRAPHIC"), std::string::npos);
  }
  try {
    WriteColmapModelBinary(image_set, dir);
    ADD_FAILURE() << "ORTHOGRAPHIC written as binary";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), (dir / "cameras.bin").string());
  }
  EXPECT_TRUE(fs::is_empty(dir));  // nothing written

  ImageSet spaced = RandomModel(3);
  spaced.views[0].name = "my photo.jpg";
  EXPECT_THROW(WriteColmapModelText(spaced, dir), InputError);
  WriteColmapModelBinary(spaced, dir);  // binary names may hold spaces
  EXPECT_EQ(ReadColmapModelBinary(dir).views[0].name, "my photo.jpg");
}

}  // namespace
}  // namespace sylva
