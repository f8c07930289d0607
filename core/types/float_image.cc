#include "core/types/float_image.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/util/check.h"

namespace sylva {

FloatImage FloatImage::Channel(int c) const {
  SYLVA_CHECK(c >= 0 && c < channels_);
  FloatImage out(width_, height_, 1);
  for (size_t i = 0; i < NumPixels(); ++i) out.data()[i] = data_[i * channels_ + c];
  return out;
}

FloatImage DownsampleBox(const FloatImage& image, int factor) {
  SYLVA_CHECK(factor >= 1 && image.channels() == 1);
  if (factor == 1) return image;
  const int out_width = (image.width() + factor - 1) / factor;
  const int out_height = (image.height() + factor - 1) / factor;
  FloatImage out(out_width, out_height, 1);
  std::vector<double> row_sums(out_width);
  for (int out_y = 0; out_y < out_height; ++out_y) {
    std::fill(row_sums.begin(), row_sums.end(), 0.0);
    const int y_end = std::min((out_y + 1) * factor, image.height());
    for (int y = out_y * factor; y < y_end; ++y) {
      // Each output pixel's columns in turn: the same sums, in the same
      // order, as adding every pixel to its output's sum along the row.
      const float* row = image.data() + static_cast<size_t>(y) * image.width();
      for (int out_x = 0; out_x < out_width; ++out_x) {
        const int x_end = std::min((out_x + 1) * factor, image.width());
        double sum = row_sums[out_x];
        for (int x = out_x * factor; x < x_end; ++x) sum += row[x];
        row_sums[out_x] = sum;
      }
    }
    const int rows = y_end - out_y * factor;
    for (int out_x = 0; out_x < out_width; ++out_x) {
      const int cols = std::min((out_x + 1) * factor, image.width()) - out_x * factor;
      out.at(out_x, out_y) = static_cast<float>(row_sums[out_x] / (rows * cols));
    }
  }
  return out;
}

SummedAreaTable::SummedAreaTable(const FloatImage& image)
    : width_(image.width()),
      height_(image.height()),
      table_(static_cast<size_t>(width_ + 1) * (height_ + 1), 0.0),
      nonzero_(table_.size(), 0) {
  SYLVA_CHECK(image.channels() == 1);
  SYLVA_CHECK(static_cast<int64_t>(width_) * height_ <= std::numeric_limits<int32_t>::max());
  const size_t stride = width_ + 1;
  for (int y = 0; y < height_; ++y) {
    double row_sum = 0.0;
    int32_t row_count = 0;
    for (int x = 0; x < width_; ++x) {
      const float value = image.at(x, y);
      row_sum += value;
      row_count += value != 0.0f;
      const size_t i = (y + 1) * stride + x + 1;
      table_[i] = table_[i - stride] + row_sum;
      nonzero_[i] = nonzero_[i - stride] + row_count;
    }
  }
}

bool SummedAreaTable::AllZero(int x0, int y0, int x1, int y1) const {
  SYLVA_DCHECK(0 <= x0 && x0 <= x1 && x1 <= width_ && 0 <= y0 && y0 <= y1 && y1 <= height_);
  const size_t stride = width_ + 1;
  return nonzero_[y1 * stride + x1] - nonzero_[y0 * stride + x1] - nonzero_[y1 * stride + x0] +
             nonzero_[y0 * stride + x0] ==
         0;
}

double SummedAreaTable::Sum(int x0, int y0, int x1, int y1) const {
  const size_t stride = width_ + 1;
  return table_[y1 * stride + x1] - table_[y0 * stride + x1] - table_[y1 * stride + x0] +
         table_[y0 * stride + x0];
}

double SummedAreaTable::BoxMean(double x0, double y0, double x1, double y1) const {
  // Pixel i has its centre at i + 0.5: it is inside [x0, x1) iff x0 <= i + 0.5 < x1.
  // Clamped just outside the image before the conversion to int (a far-out
  // coordinate would overflow it); the tests below see the same.
  const auto pixel = [](double coordinate, int size) {
    return static_cast<int>(std::clamp(std::ceil(coordinate - 0.5), -1.0, size + 1.0));
  };
  int i0 = pixel(x0, width_);
  int i1 = pixel(x1, width_);
  int j0 = pixel(y0, height_);
  int j1 = pixel(y1, height_);
  if (i1 <= 0 || j1 <= 0 || i0 >= width_ || j0 >= height_) return -1.0;
  // A footprint smaller than a pixel still samples the pixel it falls in.
  if (i1 <= i0) i1 = i0 + 1;
  if (j1 <= j0) j1 = j0 + 1;
  i0 = std::clamp(i0, 0, width_ - 1);
  j0 = std::clamp(j0, 0, height_ - 1);
  i1 = std::clamp(i1, i0 + 1, width_);
  j1 = std::clamp(j1, j0 + 1, height_);
  // Exactly 0 over zero pixels: the table's differences leave rounding dust
  // there, and a dust of -1e-15 read as "outside the image" made a view that
  // sees a voxel empty skip it in carving.
  if (AllZero(i0, j0, i1, j1)) return 0.0;
  return Sum(i0, j0, i1, j1) / (static_cast<double>(i1 - i0) * (j1 - j0));
}

}  // namespace sylva
