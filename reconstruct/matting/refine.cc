// RefineMatte (matting.h): alpha for the unknown pixels of a trimap.
#include <opencv2/core.hpp>  // alphamat.hpp needs it first

#include <opencv2/alphamat.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <cmath>

#include "core/util/check.h"
#include "reconstruct/matting/closed_form.h"
#include "reconstruct/matting/cv_image.h"
#include "reconstruct/matting/guided_upsample.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/matting/trimap.h"

namespace sylva {
namespace {

// Information flow runs on the bounding box of the unknown pixels grown by
// this fraction of its size (at least kMinCropMargin pixels), so that its
// colour samples and neighbourhoods see known pixels around the band.
constexpr double kCropMarginFraction = 0.1;
constexpr int kMinCropMargin = 16;
// Information flow needs this many known pixels of each label for its
// nearest-neighbour searches (it queries 20 neighbours); below, the crop is
// widened to the whole image.
constexpr int kMinKnownSamples = 64;

// Known pixels as 0 / 1, unknown as 0.5.
cv::Mat ClassifyTrimap(const FloatImage& trimap) {
  cv::Mat values = GrayToMat(trimap);
  cv::Mat classified(values.size(), CV_32F, cv::Scalar(kTrimapUnknown));
  classified.setTo(kTrimapBackground, values <= kTrimapBackgroundMax);
  classified.setTo(kTrimapForeground, values >= kTrimapForegroundMin);
  return classified;
}

// The trimap at the reduced size: a reduced pixel is foreground if the
// full-resolution pixels it covers include foreground but no background,
// background in the opposite case, unknown otherwise. (Requiring every
// covered pixel to be known would leave no known core in stems a few pixels
// wide, and the solve would have nothing to propagate along them.)
cv::Mat ReduceTrimap(const cv::Mat& classified, cv::Size size) {
  const auto fraction = [&](float label) {
    const cv::Mat is_label = classified == label;
    cv::Mat mask, mean;
    is_label.convertTo(mask, CV_32F, 1.0 / 255.0);
    cv::resize(mask, mean, size, 0, 0, cv::INTER_AREA);
    return mean;
  };
  const cv::Mat foreground = fraction(kTrimapForeground) > 0.0f;
  const cv::Mat background = fraction(kTrimapBackground) > 0.0f;
  cv::Mat reduced(size, CV_32F, cv::Scalar(kTrimapUnknown));
  reduced.setTo(kTrimapForeground, foreground & ~background);
  reduced.setTo(kTrimapBackground, background & ~foreground);
  return reduced;
}

cv::Rect UnknownCrop(const cv::Mat& unknown) {
  const cv::Rect box = cv::boundingRect(unknown);
  const int mx = std::max(kMinCropMargin, static_cast<int>(kCropMarginFraction * box.width));
  const int my = std::max(kMinCropMargin, static_cast<int>(kCropMarginFraction * box.height));
  const cv::Rect grown(box.x - mx, box.y - my, box.width + 2 * mx, box.height + 2 * my);
  return grown & cv::Rect(0, 0, unknown.cols, unknown.rows);
}

// Information-flow alpha (Aksoy et al. 2017) through cv::alphamat::infoFlow.
cv::Mat InfoFlowAlpha(const cv::Mat& rgb, const cv::Mat& classified) {
  const cv::Mat unknown = classified == kTrimapUnknown;
  cv::Rect crop = UnknownCrop(unknown);
  const auto count = [&](const cv::Rect& r, float label) {
    return cv::countNonZero(classified(r) == label);
  };
  if (count(crop, kTrimapForeground) < kMinKnownSamples ||
      count(crop, kTrimapBackground) < kMinKnownSamples) {
    crop = cv::Rect(0, 0, rgb.cols, rgb.rows);
  }
  cv::Mat alpha = classified.clone();
  const int num_foreground = count(crop, kTrimapForeground);
  const int num_background = count(crop, kTrimapBackground);
  if (num_foreground < kMinKnownSamples || num_background < kMinKnownSamples) {
    // Too few samples of one label for information flow: the unknown pixels
    // take the label that is present (0.5 if neither is).
    const float fill = num_foreground >= kMinKnownSamples   ? 1.0f
                       : num_background >= kMinKnownSamples ? 0.0f
                                                            : kTrimapUnknown;
    alpha.setTo(fill, unknown);
    return alpha;
  }
  cv::Mat tmap8;
  classified(crop).convertTo(tmap8, CV_8U, 255.0);  // 0 / 128 / 255
  // infoFlow logs its progress through OpenCV's logger (INFO level, off by
  // default) and overwrites its trimap argument: tmap8 is our own copy.
  cv::Mat result8;
  cv::alphamat::infoFlow(RgbToBgr8(rgb(crop)), tmap8, result8);
  cv::Mat result;
  result8.convertTo(result, CV_32F, 1.0 / 255.0);
  result.copyTo(alpha(crop), unknown(crop));
  return alpha;
}

cv::Mat ClosedFormAlpha(const cv::Mat& rgb, const cv::Mat& classified,
                        const MattingOptions& options, ProgressTask* progress,
                        MattingSummary* summary) {
  ClosedFormOptions solver;
  solver.epsilon = options.closed_form_epsilon;
  solver.max_iterations = options.closed_form_max_iterations;
  solver.tolerance = options.closed_form_tolerance;
  solver.prior_weight = options.closed_form_prior_weight;
  ClosedFormSummary solver_summary;
  const FloatImage alpha =
      ClosedFormMatte(MatToImage(rgb), MatToImage(classified), solver, progress, &solver_summary);
  if (summary != nullptr) summary->solver_iterations = solver_summary.iterations;
  return GrayToMat(alpha);
}

// Alpha of the classified trimap's unknown pixels at the trimap's resolution.
cv::Mat RefineAtScale(const cv::Mat& rgb, const cv::Mat& classified, const MattingOptions& options,
                      ProgressTask* progress, MattingSummary* summary) {
  if (options.refine == "alphamat") return InfoFlowAlpha(rgb, classified);
  SYLVA_CHECK(options.refine == "closed_form") << options.refine;
  return ClosedFormAlpha(rgb, classified, options, progress, summary);
}

void CheckTrimap(const FloatImage& trimap, const FloatImage& photo) {
  SYLVA_CHECK_INPUT(trimap.channels() == 1, "trimap")
      << "must have one channel, got " << trimap.channels();
  SYLVA_CHECK_INPUT(trimap.width() == photo.width() && trimap.height() == photo.height(), "trimap")
      << "is " << trimap.width() << "x" << trimap.height() << " but the photo is " << photo.width()
      << "x" << photo.height();
  for (size_t i = 0; i < trimap.NumPixels(); ++i) {
    const float v = trimap.values()[i];
    SYLVA_CHECK_INPUT(std::isfinite(v) && v >= 0.0f && v <= 1.0f, "trimap")
        << "value " << v << " at pixel (" << i % trimap.width() << ", " << i / trimap.width()
        << ") is not in [0, 1]";
  }
}

}  // namespace

FloatImage RefineMatte(const FloatImage& photo, const FloatImage& trimap,
                       const MattingOptions& options, ProgressTask* progress,
                       MattingSummary* summary) {
  options.Check();
  CheckPhoto(photo, "photo");
  CheckTrimap(trimap, photo);
  const cv::Mat rgb = RgbToMat(photo);
  const cv::Mat classified = ClassifyTrimap(trimap);
  const cv::Mat unknown = classified == kTrimapUnknown;
  if (cv::countNonZero(unknown) == 0) return MatToImage(classified);

  if (options.refine == "none") return MatToImage(classified);
  const int factor = ReductionFactor(rgb.size(), options.max_megapixels);
  if (summary != nullptr) summary->refine_factor = factor;
  cv::Mat alpha;
  if (factor == 1) {
    alpha = RefineAtScale(rgb, classified, options, progress, summary);
  } else {
    const cv::Size small_size = ReducedSize(rgb.size(), factor);
    cv::Mat small_rgb;
    cv::resize(rgb, small_rgb, small_size, 0, 0, cv::INTER_AREA);
    const cv::Mat small_alpha =
        RefineAtScale(small_rgb, ReduceTrimap(classified, small_size), options, progress, summary);
    alpha = GuidedUpsample(small_rgb, small_alpha, rgb, options.upsample_radius,
                           options.upsample_epsilon);
  }
  // Known pixels keep their label exactly.
  cv::Mat result = classified.clone();
  alpha.copyTo(result, unknown);
  return MatToImage(result);
}

}  // namespace sylva
