#include "core/types/float_image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace sylva {
namespace {

FloatImage Ramp(int width, int height) {
  FloatImage image(width, height, 1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.at(x, y) = static_cast<float>(x + 10 * y);
  return image;
}

TEST(FloatImageTest, DownsampleBoxAveragesIncludingPartialBlocks) {
  const FloatImage image = Ramp(5, 3);
  const FloatImage small = DownsampleBox(image, 2);
  ASSERT_EQ(small.width(), 3);
  ASSERT_EQ(small.height(), 2);
  EXPECT_FLOAT_EQ(small.at(0, 0), (0 + 1 + 10 + 11) / 4.0f);
  EXPECT_FLOAT_EQ(small.at(2, 0), (4 + 14) / 2.0f);   // last column alone
  EXPECT_FLOAT_EQ(small.at(2, 1), 24.0f);             // corner pixel alone
  EXPECT_FLOAT_EQ(small.at(1, 1), (22 + 23) / 2.0f);  // last row alone
}

// Each output pixel is the double-precision sum of its block, row by row
// and left to right within a row, over its pixel count: to the bit, on
// values whose sums round, for factors that do and do not divide the size.
TEST(FloatImageTest, DownsampleBoxSumsEachBlockInRowOrder) {
  FloatImage image(37, 23, 1);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      image.at(x, y) = static_cast<float>(std::sin(0.37 * x + 1.13 * y) * 1e3 + 1.0 / (1 + x));
    }
  }
  for (int factor = 1; factor <= 8; ++factor) {
    SCOPED_TRACE(factor);
    const FloatImage small = DownsampleBox(image, factor);
    ASSERT_EQ(small.width(), (image.width() + factor - 1) / factor);
    ASSERT_EQ(small.height(), (image.height() + factor - 1) / factor);
    for (int oy = 0; oy < small.height(); ++oy) {
      for (int ox = 0; ox < small.width(); ++ox) {
        double sum = 0.0;
        int count = 0;
        for (int y = oy * factor; y < std::min((oy + 1) * factor, image.height()); ++y) {
          for (int x = ox * factor; x < std::min((ox + 1) * factor, image.width()); ++x) {
            sum += image.at(x, y);
            ++count;
          }
        }
        const float expected = factor == 1 ? image.at(ox, oy) : static_cast<float>(sum / count);
        ASSERT_EQ(small.at(ox, oy), expected) << ox << ", " << oy;
      }
    }
  }
}

TEST(FloatImageTest, SummedAreaTableMatchesDirectMeans) {
  const FloatImage image = Ramp(8, 6);
  const SummedAreaTable table(image);
  // Pixel centres in [1, 4) x [2, 5): columns 1..3 (centres 1.5..3.5), rows 2..4.
  double sum = 0;
  for (int y = 2; y <= 4; ++y)
    for (int x = 1; x <= 3; ++x) sum += image.at(x, y);
  EXPECT_NEAR(table.BoxMean(1.0, 2.0, 4.0, 5.0), sum / 9, 1e-9);
  // A tiny box samples the pixel it falls in.
  EXPECT_NEAR(table.BoxMean(3.2, 4.2, 3.3, 4.3), image.at(3, 4), 1e-9);
  // Clipped to the image; fully outside gives -1.
  EXPECT_NEAR(table.BoxMean(-5, -5, 1, 1), image.at(0, 0), 1e-9);
  EXPECT_EQ(table.BoxMean(20, 20, 30, 30), -1.0);
}

// A box of zero pixels below and beside values of many magnitudes: the
// table's differences there leave rounding dust (7e-12 here without the
// exact test; on a matte -1e-15 made carving read a view as "outside the
// image"). Its mean is exactly 0.
TEST(FloatImageTest, BoxMeanOverZeroPixelsIsExactlyZero) {
  FloatImage image(64, 64, 1, 0.0f);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      image.at(x, y) = static_cast<float>((x * 7 + y * 13) % 10 * std::pow(10.0, (x + y) % 9 - 4));
    }
  }
  for (int y = 30; y < 50; ++y) {
    for (int x = 20; x < 40; ++x) image.at(x, y) = 0.0f;
  }
  const SummedAreaTable table(image);
  int boxes = 0;
  for (int y0 = 30; y0 < 50; ++y0) {
    for (int x0 = 20; x0 < 40; x0 += 3) {
      EXPECT_EQ(table.BoxMean(x0, y0, 40, 50), 0.0) << x0 << " " << y0;
      ++boxes;
    }
  }
  EXPECT_EQ(boxes, 140);
}

TEST(FloatImageTest, AllZeroSeesTheFaintestPixel) {
  FloatImage image(9, 7, 1, 0.0f);
  image.at(6, 5) = 1e-30f;  // lost in a sum of doubles beside large values
  image.at(0, 0) = 1e6f;
  const SummedAreaTable table(image);
  EXPECT_TRUE(table.AllZero(1, 1, 6, 5));   // ends just before the faint pixel
  EXPECT_FALSE(table.AllZero(1, 1, 7, 6));  // holds it
  EXPECT_FALSE(table.AllZero(0, 0, 1, 1));
  EXPECT_TRUE(table.AllZero(3, 3, 3, 3));  // empty range
}

TEST(FloatImageTest, ChannelExtraction) {
  FloatImage rgba(2, 1, 4);
  rgba.at(1, 0, 3) = 0.25f;
  const FloatImage alpha = rgba.Channel(3);
  EXPECT_EQ(alpha.channels(), 1);
  EXPECT_FLOAT_EQ(alpha.at(1, 0), 0.25f);
}

}  // namespace
}  // namespace sylva
