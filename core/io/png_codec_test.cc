// sylva reads and writes PNG with libpng (png_codec.h) where it used
// OpenImageIO: these tests hold the two to the same pixels, bit for bit, on
// every PNG colour type and bit depth, with palettes, transparency (tRNS),
// gamma and Adam7 interlacing. This test links OpenImageIO itself.
#include "core/io/png_codec.h"

#include <gtest/gtest.h>
#include <png.h>

#include <OpenImageIO/imageio.h>

#include <csetjmp>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_png_codec_test";
  fs::create_directories(dir);
  return dir;
}

// A PNG as libpng stores it: the samples packed as the colour type and bit
// depth say, rows of `row_bytes`.
struct RawPng {
  int width = 0;
  int height = 0;
  int color_type = PNG_COLOR_TYPE_GRAY;
  int bit_depth = 8;
  bool interlaced = false;
  std::vector<png_color> palette;
  std::vector<png_byte> palette_alpha;  // tRNS of a palette
  bool transparent_colour = false;      // tRNS of grey or RGB: the first pixel's
  double gamma = 0.0;                   // gAMA if > 0
  std::vector<png_byte> bytes;
  size_t row_bytes = 0;
};

int SamplesPerPixel(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return 2;
    case PNG_COLOR_TYPE_RGB:
      return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA:
      return 4;
    default:
      return 1;
  }
}

// Random samples (palette indices below the palette's size).
RawPng RandomPng(int color_type, int bit_depth, RandomEngine* random) {
  RawPng png;
  png.width = 13 + static_cast<int>(random->UniformInt(20));
  png.height = 7 + static_cast<int>(random->UniformInt(20));
  png.color_type = color_type;
  png.bit_depth = bit_depth;
  png.row_bytes = (size_t(png.width) * SamplesPerPixel(color_type) * bit_depth + 7) / 8;
  png.bytes.resize(png.row_bytes * png.height);
  for (png_byte& byte : png.bytes) byte = static_cast<png_byte>(random->UniformInt(256));
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    const int entries = 1 << bit_depth;
    for (int k = 0; k < entries; ++k) {
      png.palette.push_back({static_cast<png_byte>(random->UniformInt(256)),
                             static_cast<png_byte>(random->UniformInt(256)),
                             static_cast<png_byte>(random->UniformInt(256))});
    }
  }
  return png;
}

// Writes `png` with libpng as it stands (no transformation); false if
// libpng refuses.
bool WriteRaw(const fs::path& path, const RawPng& png) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return false;
  png_structp write = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(write);
  std::vector<png_bytep> rows(png.height);
  for (int y = 0; y < png.height; ++y) {
    rows[y] = const_cast<png_bytep>(png.bytes.data()) + png.row_bytes * y;
  }
  if (setjmp(png_jmpbuf(write))) {
    png_destroy_write_struct(&write, &info);
    std::fclose(file);
    return false;
  }
  png_init_io(write, file);
  png_set_IHDR(write, info, png.width, png.height, png.bit_depth, png.color_type,
               png.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!png.palette.empty()) {
    png_set_PLTE(write, info, png.palette.data(), static_cast<int>(png.palette.size()));
  }
  if (!png.palette_alpha.empty()) {
    png_set_tRNS(write, info, png.palette_alpha.data(), static_cast<int>(png.palette_alpha.size()),
                 nullptr);
  }
  if (png.transparent_colour) {
    // The first pixel's value (its first sample, or RGB) is transparent.
    png_color_16 colour{};
    const int mask = (1 << png.bit_depth) - 1;
    const auto sample = [&](int k) {
      if (png.bit_depth == 16) return (png.bytes[2 * k] << 8) | png.bytes[2 * k + 1];
      if (png.bit_depth == 8) return int{png.bytes[k]};
      return (png.bytes[0] >> (8 - png.bit_depth)) & mask;
    };
    colour.gray = static_cast<png_uint_16>(sample(0));
    colour.red = static_cast<png_uint_16>(sample(0));
    if (png.color_type == PNG_COLOR_TYPE_RGB) {
      colour.green = static_cast<png_uint_16>(sample(1));
      colour.blue = static_cast<png_uint_16>(sample(2));
    }
    png_set_tRNS(write, info, nullptr, 0, &colour);
  }
  if (png.gamma > 0) png_set_gAMA(write, info, png.gamma);
  png_write_info(write, info);
  png_write_image(write, rows.data());
  png_write_end(write, nullptr);
  png_destroy_write_struct(&write, &info);
  return std::fclose(file) == 0;
}

// OpenImageIO's reading, as sylva did it: straight alpha, floats.
FloatImage ReadWithOpenImageIo(const fs::path& path, int* alpha_channel) {
  auto input = OIIO::ImageInput::create("png");
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageSpec spec;
  EXPECT_TRUE(input->open(path.string(), spec, config)) << input->geterror();
  *alpha_channel = spec.alpha_channel;
  FloatImage image(spec.width, spec.height, spec.nchannels);
  EXPECT_TRUE(input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.data()));
  input->close();
  return image;
}

void ExpectSamePixels(const FloatImage& ours, const FloatImage& theirs) {
  ASSERT_EQ(ours.width(), theirs.width());
  ASSERT_EQ(ours.height(), theirs.height());
  ASSERT_EQ(ours.channels(), theirs.channels());
  for (size_t i = 0; i < ours.values().size(); ++i) {
    ASSERT_EQ(ours.values()[i], theirs.values()[i]) << "sample " << i;
  }
}

TEST(PngCodecTest, ReadsEveryColourTypeAsOpenImageIoDoes) {
  struct Kind {
    int color_type;
    std::vector<int> depths;
  };
  const Kind kinds[] = {{PNG_COLOR_TYPE_GRAY, {1, 2, 4, 8, 16}},
                        {PNG_COLOR_TYPE_GRAY_ALPHA, {8, 16}},
                        {PNG_COLOR_TYPE_RGB, {8, 16}},
                        {PNG_COLOR_TYPE_RGB_ALPHA, {8, 16}},
                        {PNG_COLOR_TYPE_PALETTE, {1, 2, 4, 8}}};
  RandomEngine random(11);
  int files = 0;
  for (const Kind& kind : kinds) {
    for (const int depth : kind.depths) {
      // Plain; interlaced with gamma; with tRNS (palette alpha or a
      // transparent colour) where the colour type allows it.
      for (int variant = 0; variant < 3; ++variant) {
        RawPng png = RandomPng(kind.color_type, depth, &random);
        png.interlaced = variant == 1;
        if (variant == 1) png.gamma = 1.0 / 2.2;
        if (variant == 2) {
          if (kind.color_type == PNG_COLOR_TYPE_PALETTE) {
            for (size_t k = 0; k < png.palette.size(); k += 2) {
              png.palette_alpha.push_back(static_cast<png_byte>(random.UniformInt(256)));
            }
          } else if (kind.color_type == PNG_COLOR_TYPE_GRAY ||
                     kind.color_type == PNG_COLOR_TYPE_RGB) {
            png.transparent_colour = true;
          } else {
            continue;
          }
        }
        const std::string name = "kind_" + std::to_string(kind.color_type) + "_" +
                                 std::to_string(depth) + "_" + std::to_string(variant) + ".png";
        SCOPED_TRACE(name);
        const fs::path path = TestDir() / name;
        ASSERT_TRUE(WriteRaw(path, png));
        int alpha_channel = -2;
        const FloatImage theirs = ReadWithOpenImageIo(path, &alpha_channel);
        const ImageHeader header = ReadImageHeader(path);
        EXPECT_EQ(header.width, theirs.width());
        EXPECT_EQ(header.height, theirs.height());
        EXPECT_EQ(header.channels, theirs.channels());
        EXPECT_EQ(header.alpha_channel, alpha_channel);
        ExpectSamePixels(ReadImage(path), theirs);
        ++files;
      }
    }
  }
  EXPECT_EQ(files, 15 * 2 + 11);  // 15 kinds plain and interlaced, 11 with tRNS
}

// What WritePng stores is what OpenImageIO stored for the same floats:
// rounding half up, values outside [0, 1] and NaN clamped, 8 and 16 bits,
// 1 to 4 channels (straight alpha).
TEST(PngCodecTest, WritesTheSamplesOpenImageIoWrote) {
  RandomEngine random(5);
  for (const PixelFormat format : {PixelFormat::kUint8, PixelFormat::kUint16}) {
    const bool wide = format == PixelFormat::kUint16;
    for (int channels = 1; channels <= 4; ++channels) {
      SCOPED_TRACE(std::to_string(channels) + (wide ? " channels, 16 bits" : " channels, 8 bits"));
      FloatImage image(31, 17, channels);
      const float levels = wide ? 65535.0f : 255.0f;
      for (size_t i = 0; i < image.values().size(); ++i) {
        float& value = image.values()[i];
        switch (i % 5) {
          case 0:  // exactly half-way between two levels
            value = (static_cast<float>(random.UniformInt(255)) + 0.5f) / levels;
            break;
          case 1:  // outside [0, 1]
            value = static_cast<float>(random.Uniform(-0.5, 1.5));
            break;
          default:
            value = static_cast<float>(random.Uniform());
        }
      }
      image.values()[3] = std::numeric_limits<float>::quiet_NaN();
      const fs::path ours = TestDir() / "ours.png", theirs = TestDir() / "theirs.png";
      WriteImage(ours, image, format);
      auto output = OIIO::ImageOutput::create(theirs.string());
      OIIO::ImageSpec spec(image.width(), image.height(), channels,
                           wide ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
      spec.attribute("oiio:UnassociatedAlpha", 1);
      ASSERT_TRUE(output->open(theirs.string(), spec));
      ASSERT_TRUE(output->write_image(OIIO::TypeDesc::FLOAT, image.data()));
      output->close();
      int alpha_ours = -2, alpha_theirs = -2;
      const FloatImage read_ours = ReadWithOpenImageIo(ours, &alpha_ours);
      const FloatImage read_theirs = ReadWithOpenImageIo(theirs, &alpha_theirs);
      EXPECT_EQ(alpha_ours, alpha_theirs);
      // Samples 3 (NaN): OpenImageIO's conversion of NaN is undefined; ours is 0.
      EXPECT_EQ(read_ours.values()[3], 0.0f);
      FloatImage expected = read_theirs;
      expected.values()[3] = 0.0f;
      ExpectSamePixels(read_ours, expected);
    }
  }
}

// libpng's own errors (past the chunk check) name the file in one line; a
// long strip is no error.
TEST(PngCodecTest, DecodingErrorsNameTheFile) {
  RandomEngine random(3);
  RawPng png = RandomPng(PNG_COLOR_TYPE_RGB, 8, &random);
  const fs::path path = TestDir() / "damaged_stream.png";
  ASSERT_TRUE(WriteRaw(path, png));
  std::string bytes = ReadFileToString(path);
  const size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  bytes[idat + 6] ^= 0x55;  // inside the compressed data: the CRC fails
  AtomicWriteString(path, bytes);
  try {
    ReadImage(path);
    FAIL() << "a PNG with a damaged IDAT was read";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string());
    EXPECT_NE(std::string(error.what()).find("cannot decode image"), std::string::npos)
        << error.what();
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
  }
  // Only the pixel count is limited (image_io.h), not a side: a strip of
  // 70,000 x 1 pixels reads.
  RawPng wide;
  wide.width = 70000;
  wide.height = 1;
  wide.bit_depth = 1;
  wide.row_bytes = (wide.width + 7) / 8;
  wide.bytes.assign(wide.row_bytes, 0xff);
  const fs::path wide_path = TestDir() / "wide.png";
  ASSERT_TRUE(WriteRaw(wide_path, wide));
  const FloatImage strip = ReadImage(wide_path);
  EXPECT_EQ(strip.width(), 70000);
  EXPECT_EQ(strip.at(69999, 0), 1.0f);
}

}  // namespace
}  // namespace sylva
