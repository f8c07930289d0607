// A float image with interleaved channels, row-major, values nominally in
// [0, 1]. Used for photos (3 or 4 channels) and mattes (1 channel, alpha).
#ifndef SYLVA_CORE_TYPES_FLOAT_IMAGE_H_
#define SYLVA_CORE_TYPES_FLOAT_IMAGE_H_

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sylva {

class FloatImage {
 public:
  FloatImage() = default;
  FloatImage(int width, int height, int channels, float fill = 0.0f)
      : width_(width),
        height_(height),
        channels_(channels),
        data_(static_cast<size_t>(width) * height * channels, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  bool empty() const { return data_.empty(); }
  size_t NumPixels() const { return static_cast<size_t>(width_) * height_; }

  float& at(int x, int y, int c = 0) { return data_[Offset(x, y, c)]; }
  float at(int x, int y, int c = 0) const { return data_[Offset(x, y, c)]; }
  float* data() { return data_.data(); }
  const float* data() const { return data_.data(); }
  std::vector<float>& values() { return data_; }
  const std::vector<float>& values() const { return data_; }

  // One channel as a single-channel image.
  FloatImage Channel(int c) const;

 private:
  size_t Offset(int x, int y, int c) const {
    return (static_cast<size_t>(y) * width_ + x) * channels_ + c;
  }

  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
  std::vector<float> data_;
};

// Box-filter downsampling of a single-channel image by an integer factor:
// output pixel (I, J) is the mean of input pixels [I f, min((I+1) f, w)) x
// [J f, min((J+1) f, h)), so no input pixel is dropped. factor >= 1.
FloatImage DownsampleBox(const FloatImage& image, int factor);

// Summed-area table of a single-channel image, for O(1) box averages.
class SummedAreaTable {
 public:
  explicit SummedAreaTable(const FloatImage& image);
  // Mean over the pixels whose centres lie in [x0, x1) x [y0, y1) (pixel
  // coordinates, COLMAP convention), clipped to the image; exactly 0 where
  // every pixel is 0. Returns -1 if the rectangle lies entirely outside the
  // image.
  double BoxMean(double x0, double y0, double x1, double y1) const;
  // True if every pixel of [x0, x1) x [y0, y1) (pixel indices, inside the
  // image) is exactly 0; counted in integers, so exact.
  bool AllZero(int x0, int y0, int x1, int y1) const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  double Sum(int x0, int y0, int x1, int y1) const;  // [x0,x1) x [y0,y1), in range

  int width_ = 0;
  int height_ = 0;
  std::vector<double> table_;     // (width+1) x (height+1), table_[0][*] = 0
  std::vector<int32_t> nonzero_;  // the same table of the count of non-zero pixels
};

}  // namespace sylva

#endif  // SYLVA_CORE_TYPES_FLOAT_IMAGE_H_
