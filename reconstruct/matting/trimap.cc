#include "reconstruct/matting/trimap.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "core/util/check.h"
#include "reconstruct/matting/backdrop.h"
#include "reconstruct/matting/cv_image.h"
#include "reconstruct/matting/option_parsing.h"

namespace sylva {
namespace {

// Smallest photo side (pixels) the trimap and refinement work on.
constexpr int kMinPhotoSide = 8;
// Labels are CV_8U while the trimap is built.
constexpr uchar kLabelBackground = 0;
constexpr uchar kLabelUnknown = 128;
constexpr uchar kLabelForeground = 255;
// Rejected-hue objects: less saturated pixels (by this factor) of the same
// hues join them within this radius (pixels), and holes up to about the
// closing radius are filled.
constexpr double kRejectWeakSaturationFactor = 0.6;
constexpr int kRejectGrowRadius = 3;
constexpr int kRejectCloseRadius = 3;

cv::Mat LabelsFromEvidence(const cv::Mat& e, double foreground_evidence) {
  cv::Mat labels(e.size(), CV_8U, cv::Scalar(kLabelUnknown));
  labels.setTo(kLabelBackground, e < 1.0f);
  labels.setTo(kLabelForeground, e >= static_cast<float>(foreground_evidence));
  return labels;
}

// Pixels within `band` of both a foreground and a background pixel become
// unknown.
void AddUnknownBand(int band, cv::Mat* labels) {
  if (band <= 0) return;
  cv::Mat near_foreground, near_background;
  cv::dilate(*labels == kLabelForeground, near_foreground, Disk(band));
  cv::dilate(*labels == kLabelBackground, near_background, Disk(band));
  labels->setTo(kLabelUnknown, near_foreground & near_background);
}

// Pixels in a rejected hue range at least `min_saturation` saturated and
// reject_min_value bright (255).
cv::Mat HueMask(const cv::Mat& hsv, const std::vector<HueRange>& ranges, double min_saturation,
                double min_value) {
  cv::Mat mask(hsv.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < hsv.rows; ++y) {
    for (int x = 0; x < hsv.cols; ++x) {
      const cv::Vec3f& p = hsv.at<cv::Vec3f>(y, x);
      if (p[1] < min_saturation || p[2] < min_value) continue;
      for (const HueRange& range : ranges) {
        if (range.Contains(p[0])) mask.at<uchar>(y, x) = 255;
      }
    }
  }
  return mask;
}

// Drops structures thinner than reject_min_width_px, grows into
// `near_rejected_extra` close by, fills holes, adds the margin.
cv::Mat CleanRejected(cv::Mat rejected, const cv::Mat& near_rejected_extra,
                      const MattingOptions& options) {
  const int open_radius = (options.reject_min_width_px - 1) / 2;
  if (open_radius > 0) cv::morphologyEx(rejected, rejected, cv::MORPH_OPEN, Disk(open_radius));
  if (!near_rejected_extra.empty()) {
    cv::Mat near;
    cv::dilate(rejected, near, Disk(kRejectGrowRadius));
    rejected |= near_rejected_extra & near;
  }
  cv::morphologyEx(rejected, rejected, cv::MORPH_CLOSE, Disk(kRejectCloseRadius));
  if (options.reject_margin_px > 0) cv::dilate(rejected, rejected, Disk(options.reject_margin_px));
  return rejected;
}

// The rejected objects (see MattingOptions::reject_hues and
// reject_below_value): strongly saturated seeds without their one- or
// two-pixel fringes (the chroma-smeared edges of tan stems over a dark
// backdrop), grown into the less saturated pixels of the same hues close by
// (highlights, folds), holes closed, plus the margin; the same for dark pixels.
cv::Mat RejectedMask(const cv::Mat& rgb, const MattingOptions& options) {
  cv::Mat rejected(rgb.size(), CV_8U, cv::Scalar(0));
  const std::vector<HueRange> ranges = ParseHueRanges(options.reject_hues);
  if (ranges.empty() && options.reject_below_value <= 0) return rejected;
  cv::Mat hsv;  // float input: H in degrees [0, 360), S and V in [0, 1]
  cv::cvtColor(rgb, hsv, cv::COLOR_RGB2HSV);
  if (!ranges.empty()) {
    const cv::Mat seeds =
        HueMask(hsv, ranges, options.reject_min_saturation, options.reject_min_value);
    const cv::Mat weak =
        HueMask(hsv, ranges, kRejectWeakSaturationFactor * options.reject_min_saturation,
                options.reject_min_value);
    rejected |= CleanRejected(seeds, weak, options);
  }
  if (options.reject_below_value > 0) {
    std::vector<cv::Mat> channels;
    cv::split(hsv, channels);
    rejected |= CleanRejected(channels[2] < options.reject_below_value, cv::Mat(), options);
  }
  return rejected;
}

// 255 outside the region of interest.
cv::Mat OutsideRegionMask(cv::Size size, const MattingOptions& options) {
  cv::Mat outside(size, CV_8U, cv::Scalar(0));
  const std::optional<RegionFraction> region = ParseRegion(options.region);
  if (!region) return outside;
  outside.setTo(255);
  const cv::Point top_left(static_cast<int>(std::lround(region->x0 * size.width)),
                           static_cast<int>(std::lround(region->y0 * size.height)));
  const cv::Point bottom_right(static_cast<int>(std::lround(region->x1 * size.width)),
                               static_cast<int>(std::lround(region->y1 * size.height)));
  outside(cv::Rect(top_left, bottom_right)).setTo(0);
  return outside;
}

cv::Mat HintLabels(const FloatImage& hint) {
  const cv::Mat h = GrayToMat(hint);
  cv::Mat labels(h.size(), CV_8U, cv::Scalar(kLabelUnknown));
  labels.setTo(kLabelBackground, h <= kTrimapBackgroundMax);
  labels.setTo(kLabelForeground, h >= kTrimapForegroundMin);
  return labels;
}

// Seeds OpenCV's global generator for the duration of a scope (GrabCut's
// k-means uses it), restoring it afterwards.
class ScopedCvSeed {
 public:
  explicit ScopedCvSeed(int seed) : saved_(cv::theRNG()) {
    cv::theRNG() = cv::RNG(0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(seed));
  }
  ~ScopedCvSeed() { cv::theRNG() = saved_; }

 private:
  cv::RNG saved_;
};

// GrabCut's foreground (255) at the photo's size. The border strip, the
// hint's background, rejected hues and the outside of the region are hard
// background; the hint's foreground is hard foreground.
cv::Mat GrabCutForeground(const cv::Mat& rgb, const cv::Mat& hard_background,
                          const cv::Mat& hint_labels, const MattingOptions& options,
                          int* factor_out) {
  const int factor = ReductionFactor(rgb.size(), options.grabcut_max_megapixels);
  *factor_out = factor;
  const cv::Size small_size = ReducedSize(rgb.size(), factor);
  cv::Mat small_rgb, small_hard, small_hint;
  cv::resize(rgb, small_rgb, small_size, 0, 0, cv::INTER_AREA);
  cv::resize(hard_background, small_hard, small_size, 0, 0, cv::INTER_NEAREST);
  cv::Mat mask(small_size, CV_8U, cv::Scalar(cv::GC_BGD));
  const int margin_x =
      std::max(1, static_cast<int>(std::lround(options.grabcut_margin * small_size.width)));
  const int margin_y =
      std::max(1, static_cast<int>(std::lround(options.grabcut_margin * small_size.height)));
  mask(cv::Rect(margin_x, margin_y, small_size.width - 2 * margin_x,
                small_size.height - 2 * margin_y))
      .setTo(cv::GC_PR_FGD);
  mask.setTo(cv::GC_BGD, small_hard);
  if (!hint_labels.empty()) {
    cv::resize(hint_labels, small_hint, small_size, 0, 0, cv::INTER_NEAREST);
    mask.setTo(cv::GC_BGD, small_hint == kLabelBackground);
    mask.setTo(cv::GC_FGD, small_hint == kLabelForeground);
  }
  // GrabCut needs samples of both labels; painted or rejected everywhere,
  // the answer is already known.
  if (cv::countNonZero(mask != cv::GC_BGD) == 0) return cv::Mat(rgb.size(), CV_8U, cv::Scalar(0));
  if (cv::countNonZero(mask != cv::GC_FGD) == 0) return cv::Mat(rgb.size(), CV_8U, cv::Scalar(255));
  {
    ScopedCvSeed seed(options.seed);
    cv::Mat background_model, foreground_model;
    cv::grabCut(RgbToBgr8(small_rgb), mask, cv::Rect(), background_model, foreground_model,
                options.grabcut_iterations, cv::GC_INIT_WITH_MASK);
  }
  const cv::Mat small_labels = (mask == cv::GC_FGD) | (mask == cv::GC_PR_FGD);
  cv::Mat small_foreground, foreground;
  small_labels.convertTo(small_foreground, CV_32F, 1.0 / 255);
  cv::resize(small_foreground, foreground, rgb.size(), 0, 0, cv::INTER_LINEAR);
  return foreground >= 0.5f;
}

FloatImage LabelsToTrimap(const cv::Mat& labels) {
  cv::Mat values;
  labels.convertTo(values, CV_32F, 1.0 / 255.0);
  values.setTo(kTrimapUnknown, labels == kLabelUnknown);
  return MatToImage(values);
}

std::string ResolveSource(const MattingOptions& options, const FloatImage& background_photo,
                          const BackdropKey& key) {
  if (options.trimap != "auto") return options.trimap;
  if (!background_photo.empty()) return "difference";
  return key.border_agreement >= options.auto_backdrop_fraction ? "backdrop" : "grabcut";
}

}  // namespace

void CheckPhoto(const FloatImage& photo, const char* what) {
  SYLVA_CHECK_INPUT(!photo.empty(), what) << "is empty";
  SYLVA_CHECK_INPUT(photo.width() >= kMinPhotoSide && photo.height() >= kMinPhotoSide, what)
      << "is " << photo.width() << "x" << photo.height() << " pixels; at least " << kMinPhotoSide
      << "x" << kMinPhotoSide << " are needed";
  SYLVA_CHECK_INPUT(photo.channels() == 3 || photo.channels() == 4, what)
      << "must be RGB or RGBA, got " << photo.channels() << " channels";
  for (float v : photo.values()) {
    SYLVA_CHECK_INPUT(std::isfinite(v), what) << "has non-finite values";
  }
}

void CheckPhotos(const FloatImage& photo, const FloatImage& background_photo) {
  CheckPhoto(photo, "photo");
  if (background_photo.empty()) return;
  CheckPhoto(background_photo, "background photo");
  SYLVA_CHECK_INPUT(
      background_photo.width() == photo.width() && background_photo.height() == photo.height(),
      "background photo")
      << "is " << background_photo.width() << "x" << background_photo.height()
      << " but the photo is " << photo.width() << "x" << photo.height();
}

FloatImage ComputeAutomaticTrimap(const FloatImage& photo, const MattingOptions& options,
                                  const FloatImage& background_photo, const FloatImage& hint,
                                  MattingSummary* summary) {
  const cv::Mat rgb = RgbToMat(photo);
  const BackdropKey key = EstimateBackdropKey(rgb, options);
  const std::string source = ResolveSource(options, background_photo, key);
  SYLVA_CHECK_INPUT(source != "difference" || !background_photo.empty(), "Matting.trimap")
      << "'difference' needs a background photo";
  const cv::Mat hard_background =
      RejectedMask(rgb, options) | OutsideRegionMask(rgb.size(), options);
  cv::Mat labels;
  if (source == "grabcut") {
    int factor = 1;
    const cv::Mat foreground = GrabCutForeground(
        rgb, hard_background, hint.empty() ? cv::Mat() : HintLabels(hint), options, &factor);
    labels = cv::Mat(rgb.size(), CV_8U, cv::Scalar(kLabelBackground));
    labels.setTo(kLabelForeground, foreground);
    // GrabCut's edges are only as fine as its reduced image.
    AddUnknownBand(std::max(options.band_px, factor), &labels);
  } else {
    const cv::Mat evidence = BackdropEvidence(
        rgb, options, key, source == "difference" ? RgbToMat(background_photo) : cv::Mat());
    labels = LabelsFromEvidence(evidence, options.foreground_evidence);
    AddUnknownBand(options.band_px, &labels);
  }
  labels.setTo(kLabelBackground, hard_background);
  if (summary != nullptr) {
    summary->trimap_source = source;
    summary->backdrop_rgb = key.seed_rgb;
    summary->border_agreement = key.border_agreement;
  }
  return LabelsToTrimap(labels);
}

FloatImage ComputeTrimap(const FloatImage& photo, const MattingOptions& options,
                         const FloatImage& background_photo) {
  options.Check();
  CheckPhotos(photo, background_photo);
  return ComputeAutomaticTrimap(photo, options, background_photo, FloatImage(), nullptr);
}

}  // namespace sylva
