#include "reconstruct/matting/trimap_io.h"

#include <cmath>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "reconstruct/matting/matting.h"

namespace sylva {
namespace {

// Largest channel spread of a pixel that still counts as grey.
constexpr float kGreyTolerance = 2.0f / 255.0f;
constexpr float kPaintedAlpha = 0.5f;

float Classify(float value) {
  if (value <= kTrimapBackgroundMax) return kTrimapBackground;
  if (value >= kTrimapForegroundMin) return kTrimapForeground;
  return kTrimapUnknown;
}

}  // namespace

FloatImage ReadHintTrimap(const std::filesystem::path& path) {
  const FloatImage image = ReadImage(path);
  const int channels = image.channels();
  SYLVA_CHECK_INPUT(channels >= 1 && channels <= 4, path.string())
      << "hint trimap has " << channels << " channels; expected grey, grey+alpha, RGB or RGBA";
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour_channels = has_alpha ? channels - 1 : channels;
  FloatImage hint(image.width(), image.height(), 1);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      float lo = 1.0f, hi = 0.0f;
      for (int c = 0; c < colour_channels; ++c) {
        lo = std::min(lo, image.at(x, y, c));
        hi = std::max(hi, image.at(x, y, c));
      }
      SYLVA_CHECK_INPUT(lo >= 0.0f && hi <= 1.0f, path.string())
          << "hint trimap value outside [0, 1] at pixel (" << x << ", " << y << ")";
      SYLVA_CHECK_INPUT(hi - lo <= kGreyTolerance, path.string())
          << "hint trimap must be grey (R = G = B), but pixel (" << x << ", " << y
          << ") is coloured; paint black = background, white = foreground, grey 128 = unpainted";
      const bool painted = !has_alpha || image.at(x, y, channels - 1) >= kPaintedAlpha;
      hint.at(x, y) = painted ? Classify(image.at(x, y, 0)) : kTrimapUnknown;
    }
  }
  return hint;
}

void WriteTrimap(const std::filesystem::path& path, const FloatImage& trimap) {
  SYLVA_CHECK(trimap.channels() == 1) << "a trimap has one channel";
  FloatImage out(trimap.width(), trimap.height(), 1);
  for (size_t i = 0; i < trimap.NumPixels(); ++i) {
    const float label = Classify(trimap.values()[i]);
    out.values()[i] = label == kTrimapUnknown ? 128.0f / 255.0f : label;
  }
  WriteImage(path, out, PixelFormat::kUint8);
}

}  // namespace sylva
