#include "reconstruct/matting/matte_tools.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "core/util/check.h"
#include "reconstruct/matting/cv_image.h"
#include "reconstruct/matting/matting.h"

namespace sylva {

FloatImage AlphaOf(const FloatImage& cutout) {
  SYLVA_CHECK(cutout.channels() == 2 || cutout.channels() == 4)
      << "a cut-out needs an alpha channel, got " << cutout.channels() << " channels";
  return cutout.Channel(cutout.channels() - 1);
}

FloatImage PadCutout(const FloatImage& cutout, int margin) {
  SYLVA_CHECK(margin >= 0);
  FloatImage padded(cutout.width() + 2 * margin, cutout.height() + 2 * margin, cutout.channels());
  for (int y = 0; y < cutout.height(); ++y) {
    for (int x = 0; x < cutout.width(); ++x) {
      for (int c = 0; c < cutout.channels(); ++c) {
        padded.at(x + margin, y + margin, c) = cutout.at(x, y, c);
      }
    }
  }
  return padded;
}

FloatImage CompositeOver(const FloatImage& cutout, const FloatImage& background) {
  SYLVA_CHECK(cutout.channels() == 2 || cutout.channels() == 4);
  SYLVA_CHECK(background.channels() >= 3 && background.width() >= cutout.width() &&
              background.height() >= cutout.height())
      << "background must be RGB(A) and at least as large as the cut-out";
  const int alpha_channel = cutout.channels() - 1;
  FloatImage out(cutout.width(), cutout.height(), 3);
  for (int y = 0; y < cutout.height(); ++y) {
    for (int x = 0; x < cutout.width(); ++x) {
      const float a = cutout.at(x, y, alpha_channel);
      for (int c = 0; c < 3; ++c) {
        const float f = cutout.at(x, y, alpha_channel == 1 ? 0 : c);
        out.at(x, y, c) = a * f + (1.0f - a) * background.at(x, y, c);
      }
    }
  }
  return out;
}

FloatImage TrimapFromAlpha(const FloatImage& alpha, int radius, float tolerance) {
  SYLVA_CHECK(alpha.channels() == 1 && radius >= 0);
  const cv::Mat a = GrayToMat(alpha);
  cv::Mat foreground = a >= 1.0f - tolerance;
  cv::Mat background = a <= tolerance;
  if (radius > 0) {
    const cv::Mat disk =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::erode(foreground, foreground, disk);
    cv::erode(background, background, disk);
  }
  cv::Mat trimap(a.size(), CV_32F, cv::Scalar(kTrimapUnknown));
  trimap.setTo(kTrimapForeground, foreground);
  trimap.setTo(kTrimapBackground, background);
  return MatToImage(trimap);
}

FloatImage DownsampleChannels(const FloatImage& image, int factor) {
  SYLVA_CHECK(factor >= 1);
  if (factor == 1) return image;
  FloatImage reduced;
  for (int c = 0; c < image.channels(); ++c) {
    const FloatImage channel = DownsampleBox(image.Channel(c), factor);
    if (reduced.empty()) reduced = FloatImage(channel.width(), channel.height(), image.channels());
    for (size_t i = 0; i < channel.NumPixels(); ++i) {
      reduced.values()[i * image.channels() + c] = channel.values()[i];
    }
  }
  return reduced;
}

FloatImage TileMirrored(const FloatImage& image, int width, int height) {
  SYLVA_CHECK(image.channels() >= 3 && !image.empty());
  const auto mirror = [](int i, int n) {
    const int m = i % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  };
  FloatImage out(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        out.at(x, y, c) = image.at(mirror(x, image.width()), mirror(y, image.height()), c);
      }
    }
  }
  return out;
}

MatteErrors CompareMattes(const FloatImage& matte, const FloatImage& reference) {
  SYLVA_CHECK(matte.channels() == 1 && reference.channels() == 1 &&
              matte.width() == reference.width() && matte.height() == reference.height())
      << "mattes must be single-channel and the same size";
  MatteErrors errors;
  double squared = 0.0;
  for (size_t i = 0; i < matte.NumPixels(); ++i) {
    const double d = matte.values()[i] - reference.values()[i];
    errors.sad += std::abs(d);
    squared += d * d;
  }
  const double n = std::max<size_t>(1, matte.NumPixels());
  errors.mse = squared / n;
  errors.mad = errors.sad / n;
  return errors;
}

}  // namespace sylva
