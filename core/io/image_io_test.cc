#include "core/io/image_io.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_image_io_test";
  fs::create_directories(dir);
  return dir;
}

FloatImage Gradient(int channels) {
  FloatImage image(16, 8, channels);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < channels; ++c) image.at(x, y, c) = (x + y * 16) / 127.0f;
  return image;
}

TEST(ImageIoTest, RoundTripFormatsAndDepths) {
  struct Case {
    const char* name;
    PixelFormat format;
    float tolerance;
  };
  const Case cases[] = {{"a.png", PixelFormat::kUint8, 0.5f / 255},
                        {"a16.png", PixelFormat::kUint16, 0.5f / 65535},
                        {"a.tif", PixelFormat::kUint16, 0.5f / 65535},
                        {"a.exr", PixelFormat::kFloat, 1e-6f},
                        {"a.jpg", PixelFormat::kUint8, 0.05f}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const int channels = std::string(c.name) == "a.jpg" ? 3 : 1;
    const FloatImage image = Gradient(channels);
    const fs::path path = TestDir() / c.name;
    WriteImage(path, image, c.format);
    const ImageHeader header = ReadImageHeader(path);
    EXPECT_EQ(header.width, 16);
    EXPECT_EQ(header.height, 8);
    const FloatImage back = ReadImage(path);
    ASSERT_EQ(back.channels(), channels);
    for (size_t i = 0; i < image.values().size(); ++i) {
      ASSERT_NEAR(back.values()[i], image.values()[i], c.tolerance);
    }
  }
}

TEST(ImageIoTest, RgbaIsStraightAlphaBothWays) {
  // Colour must survive low and zero alpha unchanged: no premultiplication on
  // reading, no division by alpha on writing.
  FloatImage image(2, 1, 4);
  const float pixels[8] = {0.6f, 0.2f, 0.4f, 0.1f, 0.8f, 0.4f, 0.2f, 0.0f};
  std::copy(pixels, pixels + 8, image.data());
  for (const char* name : {"straight.png", "straight.tif"}) {
    SCOPED_TRACE(name);
    const fs::path path = TestDir() / name;
    WriteImage(path, image, PixelFormat::kUint8);
    const FloatImage back = ReadImage(path);
    ASSERT_EQ(back.channels(), 4);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(back.data()[i], pixels[i], 0.51f / 255) << i;
  }
}

TEST(ImageIoTest, MatteFromAlphaGrayOrGrayRgb) {
  FloatImage rgba(4, 2, 4, 0.2f);
  rgba.at(1, 1, 3) = 1.0f;
  rgba.at(0, 0, 3) = 0.0f;
  WriteImage(TestDir() / "rgba.png", rgba);
  const FloatImage alpha = ReadMatte(TestDir() / "rgba.png");
  EXPECT_EQ(alpha.channels(), 1);
  EXPECT_NEAR(alpha.at(1, 1), 1.0f, 1e-6);
  EXPECT_NEAR(alpha.at(2, 1), 0.2f, 0.5f / 255);

  FloatImage gray_rgb(4, 2, 3, 0.6f);
  WriteImage(TestDir() / "gray_rgb.png", gray_rgb);
  EXPECT_NEAR(ReadMatte(TestDir() / "gray_rgb.png").at(3, 1), 0.6f, 0.5f / 255);

  // Grey+alpha with alpha opaque everywhere: the grey values are the matte.
  FloatImage gray_alpha(4, 2, 2, 1.0f);
  gray_alpha.at(0, 0, 0) = 0.0f;
  gray_alpha.at(2, 1, 0) = 0.4f;
  WriteImage(TestDir() / "gray_alpha.png", gray_alpha);
  const FloatImage from_gray = ReadMatte(TestDir() / "gray_alpha.png");
  EXPECT_NEAR(from_gray.at(0, 0), 0.0f, 1e-6);
  EXPECT_NEAR(from_gray.at(2, 1), 0.4f, 0.5f / 255);
  EXPECT_NEAR(from_gray.at(3, 1), 1.0f, 1e-6);

  FloatImage colour(4, 2, 3, 0.1f);
  colour.at(2, 1, 1) = 0.9f;
  WriteImage(TestDir() / "colour.png", colour);
  EXPECT_THROW(ReadMatte(TestDir() / "colour.png"), InputError);
}

TEST(ImageIoTest, MissingAndCorruptFilesAreInputErrors) {
  EXPECT_THROW(ReadImage(TestDir() / "missing.png"), InputError);
  AtomicWriteString(TestDir() / "corrupt.png", "\x89PNG\r\n\x1a\n this is not a png");
  try {
    ReadImage(TestDir() / "corrupt.png");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), (TestDir() / "corrupt.png").string());
  }
  // A truncated file: a valid PNG cut in half.
  const FloatImage image = Gradient(3);
  WriteImage(TestDir() / "whole.png", image);
  const std::string bytes = ReadFileToString(TestDir() / "whole.png");
  AtomicWriteString(TestDir() / "half.png", bytes.substr(0, bytes.size() / 2));
  try {
    ReadImage(TestDir() / "half.png");
    FAIL() << "a truncated PNG was read";
  } catch (const InputError& error) {
    // OpenImageIO complains in several lines; the error is one line.
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
  }
}

// The PNG's chunks are checked before decoding: the error says where the
// file breaks.
TEST(ImageIoTest, DamagedPngSaysWhereItBreaks) {
  WriteImage(TestDir() / "chunks.png", Gradient(3));
  const std::string bytes = ReadFileToString(TestDir() / "chunks.png");
  ASSERT_EQ(bytes.substr(12, 4), "IHDR");
  ASSERT_EQ(bytes.substr(bytes.size() - 8, 4), "IEND");
  const auto message = [](const std::string& content) {
    const fs::path path = TestDir() / "damaged.png";
    AtomicWriteString(path, content);
    try {
      ReadImage(path);
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string());
      return std::string(error.what());
    }
    return std::string("read");
  };
  // Cut inside a chunk, just before IEND, and with IEND's type damaged.
  EXPECT_NE(message(bytes.substr(0, 40)).find("(truncated)"), std::string::npos);
  EXPECT_NE(message(bytes.substr(0, bytes.size() - 12)).find("before its IEND chunk"),
            std::string::npos);
  std::string no_iend = bytes;
  no_iend[no_iend.size() - 8] = '%';
  EXPECT_NE(message(no_iend).find("no valid chunk at byte " + std::to_string(bytes.size() - 12)),
            std::string::npos);
  // A chunk other than IHDR first.
  std::string no_ihdr = bytes;
  no_ihdr[12] = 'X';
  EXPECT_NE(message(no_ihdr).find("does not start with its IHDR"), std::string::npos);
  // A huge chunk length.
  std::string huge = bytes;
  huge[33] = '\x7f';
  EXPECT_NE(message(huge).find("the file ends at byte " + std::to_string(bytes.size())),
            std::string::npos);
  // The whole file, and bytes after IEND, are fine.
  EXPECT_EQ(message(bytes), "read");
  EXPECT_EQ(message(bytes + "trailing"), "read");
}

// The format is told by the content: a JPEG named .png reads, a text file
// named .png is refused at once.
TEST(ImageIoTest, FormatFromContentNotExtension) {
  const FloatImage image = Gradient(3);
  WriteImage(TestDir() / "photo.jpg", image);
  fs::copy_file(TestDir() / "photo.jpg", TestDir() / "photo_named.png",
                fs::copy_options::overwrite_existing);
  const FloatImage read = ReadImage(TestDir() / "photo_named.png");
  EXPECT_EQ(read.width(), image.width());
  EXPECT_EQ(read.channels(), 3);
  for (const char* content : {"a text file", "", "GIF89a", "MMMM not a TIFF"}) {
    AtomicWriteString(TestDir() / "text.png", content);
    try {
      ReadImage(TestDir() / "text.png");
      FAIL() << "read '" << content << "' as an image";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("not an image sylva reads"), std::string::npos)
          << error.what();
    }
  }
}

TEST(ImageIoTest, TruncatedJpegIsRefused) {
  // libjpeg decodes a truncated JPEG "successfully", padding it with grey.
  const fs::path path = TestDir() / "truncated.jpg";
  FloatImage image(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = ((x * 7 + y * 13 + c * 5) % 17) / 16.0f;
  WriteImage(path, image);
  EXPECT_NO_THROW(ReadImage(path));
  const std::string bytes = ReadFileToString(path);
  AtomicWriteString(path, bytes.substr(0, bytes.size() / 2));
  try {
    ReadImage(path);
    FAIL() << "a truncated JPEG was read";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
  }
}

// A small file can state a huge image (a compressed PNG, a JPEG header):
// above 2^28 pixels it is refused from its header, before any pixel is
// allocated, through libpng and through OpenImageIO alike. Its header still
// reads.
TEST(ImageIoTest, HugeImagesAreRefusedBeforeDecoding) {
  const auto chunk = [](const std::string& type, const std::string& data) {
    std::string bytes;
    for (int shift : {24, 16, 8, 0}) bytes += static_cast<char>((data.size() >> shift) & 0xff);
    const std::string body = type + data;
    const uLong crc =
        crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
    bytes += body;
    for (int shift : {24, 16, 8, 0}) bytes += static_cast<char>((crc >> shift) & 0xff);
    return bytes;
  };
  // 20,000 x 20,000 RGB, 8 bits: 400 megapixels in 70 bytes.
  const std::string ihdr("\x00\x00\x4e\x20\x00\x00\x4e\x20\x08\x02\x00\x00\x00", 13);
  const fs::path png = TestDir() / "huge.png";
  AtomicWriteString(png, "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr) +
                             chunk("IDAT", std::string("\x78\x01", 2)) + chunk("IEND", ""));
  // The seed JPEG (12 x 9) with its frame header saying 20,000 x 20,000.
  std::string jpeg = ReadFileToString(fs::path(SYLVA_SOURCE_DIR) / "fuzz/seeds/photo.jpg");
  const size_t sof = jpeg.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  jpeg.replace(sof + 5, 4, std::string("\x4e\x20\x4e\x20", 4));
  const fs::path huge_jpeg = TestDir() / "huge.jpg";
  AtomicWriteString(huge_jpeg, jpeg);
  for (const fs::path& path : {png, huge_jpeg}) {
    SCOPED_TRACE(path.string());
    const ImageHeader header = ReadImageHeader(path);
    EXPECT_EQ(header.width, 20000);
    EXPECT_EQ(header.height, 20000);
    try {
      ReadImage(path);
      FAIL() << "a 400-megapixel image was decoded";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string());
      EXPECT_NE(std::string(error.what()).find("20000 x 20000 pixels is larger than sylva decodes"),
                std::string::npos)
          << error.what();
    }
  }
}

// Without the OpenImageIO module a JPEG photo is an error that names the
// module and where it was looked for (in a fresh process: the module loads
// once per process).
TEST(ImageIoDeathTest, MissingOpenImageIoModuleIsNamed) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path photo = fs::path(SYLVA_SOURCE_DIR) / "datasets/opencv-alphamat-plant/plant.jpg";
  EXPECT_EXIT(
      {
        setenv("SYLVA_OIIO_PLUGIN", "/nonexistent/libsylva_oiio.so", 1);
        try {
          ReadImage(photo);
        } catch (const Error& error) {
          std::fprintf(stderr, "%s\n", error.what());
          std::exit(3);
        }
        std::exit(0);
      },
      testing::ExitedWithCode(3),
      "libsylva_oiio.so. is missing .looked for /nonexistent/libsylva_oiio.so.");
}

TEST(ImageIoTest, FindMatteFileBySameRelativeName) {
  const fs::path mattes = TestDir() / "mattes";
  fs::create_directories(mattes / "side");
  WriteImage(mattes / "side" / "30.png", FloatImage(2, 2, 1));
  EXPECT_EQ(FindMatteFile(mattes, "side/30.jpg"), mattes / "side" / "30.png");
  EXPECT_TRUE(FindMatteFile(mattes, "side/31.jpg").empty());
}

TEST(ImageIoTest, ListImageFilesRecursiveSortedSkippingHiddenAndOthers) {
  const fs::path dir = TestDir() / "listing";
  fs::remove_all(dir);
  fs::create_directories(dir / "side");
  fs::create_directories(dir / ".thumbnails");
  for (const char* name : {"b.JPG", "a.png", "side/30.jpeg", "notes.txt", ".hidden.png",
                           ".thumbnails/a.png", "side/top.TIFF"}) {
    AtomicWriteString(dir / name, "x");
  }
  const std::vector<std::string> expected = {"a.png", "b.JPG", "side/30.jpeg", "side/top.TIFF"};
  EXPECT_EQ(ListImageFiles(dir), expected);
  EXPECT_THROW(ListImageFiles(dir / "missing"), InputError);
}

}  // namespace
}  // namespace sylva
