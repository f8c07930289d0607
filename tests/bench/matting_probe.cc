// Mattes one photo and, given a ground-truth silhouette, reports the IoU of
// the matte thresholded at 0.5: the by-hand check behind the matting
// defaults and the recommended option sets (numbers in the matting report).
//
//   sylva_matting_probe PHOTO [--silhouette=S.png] [--hint=H.png]
//       [--background=B.jpg] [--given_trimap=T.png] [--reference=R.png]
//       [--matte=OUT.png] [--trimap=OUT.png] [--overlay=OUT.png]
//       [--side_by_side=OUT.png] [--scale=F] [--<MattingOptions field>=value ...]
//
// --scale box-downsamples every input by an integer factor first. With
// --given_trimap the photo is only refined (RefineMatte) with that trimap;
// --reference reports the mean absolute difference to a reference matte
// over all pixels and over the trimap's unknown pixels. The overlay shows the
// photo where alpha is 1 and magenta where it is 0; with a silhouette,
// missed foreground is red and false foreground blue. The side-by-side
// picture is photo | trimap | matte | reference.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "datasets/eval/silhouette_metrics.h"
#include "reconstruct/matting/matte_tools.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/matting/trimap_io.h"

namespace sylva {
namespace {

struct ProbeFlags {
  std::string silhouette, hint, background, given_trimap, reference;
  std::string matte, trimap, overlay, side_by_side;
  int scale = 1;
};

bool ApplyMattingFlag(const std::string& name, const std::string& value, MattingOptions* o) {
  if (name == "trimap_source")
    o->trimap = value;
  else if (name == "backdrop_color")
    o->backdrop_color = value;
  else if (name == "auto_backdrop_fraction")
    o->auto_backdrop_fraction = std::stod(value);
  else if (name == "border_fraction")
    o->border_fraction = std::stod(value);
  else if (name == "chroma_tolerance")
    o->chroma_tolerance = std::stod(value);
  else if (name == "luminance_tolerance")
    o->luminance_tolerance = std::stod(value);
  else if (name == "dark_level")
    o->dark_level = std::stod(value);
  else if (name == "foreground_evidence")
    o->foreground_evidence = std::stod(value);
  else if (name == "backdrop_smoothness")
    o->backdrop_smoothness = std::stod(value);
  else if (name == "band_px")
    o->band_px = std::stoi(value);
  else if (name == "reject_hues")
    o->reject_hues = value;
  else if (name == "reject_min_saturation")
    o->reject_min_saturation = std::stod(value);
  else if (name == "reject_min_value")
    o->reject_min_value = std::stod(value);
  else if (name == "reject_min_width_px")
    o->reject_min_width_px = std::stoi(value);
  else if (name == "reject_margin_px")
    o->reject_margin_px = std::stoi(value);
  else if (name == "reject_below_value")
    o->reject_below_value = std::stod(value);
  else if (name == "region")
    o->region = value;
  else if (name == "grabcut_iterations")
    o->grabcut_iterations = std::stoi(value);
  else if (name == "grabcut_margin")
    o->grabcut_margin = std::stod(value);
  else if (name == "grabcut_max_megapixels")
    o->grabcut_max_megapixels = std::stod(value);
  else if (name == "refine")
    o->refine = value;
  else if (name == "max_megapixels")
    o->max_megapixels = std::stod(value);
  else if (name == "closed_form_epsilon")
    o->closed_form_epsilon = std::stod(value);
  else if (name == "closed_form_max_iterations")
    o->closed_form_max_iterations = std::stoi(value);
  else if (name == "closed_form_tolerance")
    o->closed_form_tolerance = std::stod(value);
  else if (name == "upsample_radius")
    o->upsample_radius = std::stoi(value);
  else if (name == "upsample_epsilon")
    o->upsample_epsilon = std::stod(value);
  else if (name == "seed")
    o->seed = std::stoi(value);
  else
    return false;
  return true;
}

bool ApplyFlag(const std::string& name, const std::string& value, ProbeFlags* flags,
               MattingOptions* options) {
  if (name == "silhouette")
    flags->silhouette = value;
  else if (name == "hint")
    flags->hint = value;
  else if (name == "background")
    flags->background = value;
  else if (name == "given_trimap")
    flags->given_trimap = value;
  else if (name == "reference")
    flags->reference = value;
  else if (name == "side_by_side")
    flags->side_by_side = value;
  else if (name == "matte")
    flags->matte = value;
  else if (name == "trimap")
    flags->trimap = value;
  else if (name == "overlay")
    flags->overlay = value;
  else if (name == "scale")
    flags->scale = std::stoi(value);
  else
    return ApplyMattingFlag(name, value, options);
  return true;
}

FloatImage Overlay(const FloatImage& photo, const FloatImage& alpha, const FloatImage& truth) {
  FloatImage out(photo.width(), photo.height(), 3);
  const float magenta[3] = {0.55f, 0.0f, 0.55f};
  for (int y = 0; y < photo.height(); ++y) {
    for (int x = 0; x < photo.width(); ++x) {
      const float a = alpha.at(x, y);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = a * photo.at(x, y, c) + (1 - a) * magenta[c];
      if (truth.empty()) continue;
      const bool ours = a >= 0.5f, theirs = truth.at(x, y) >= 0.5f;
      if (ours == theirs) continue;
      out.at(x, y, 0) = theirs ? 1.0f : 0.0f;  // missed: red; false: blue
      out.at(x, y, 1) = 0.0f;
      out.at(x, y, 2) = theirs ? 0.0f : 1.0f;
    }
  }
  return out;
}

// Mean absolute difference over all pixels and over the trimap's unknown ones.
void ReportDifference(const FloatImage& alpha, const FloatImage& reference,
                      const FloatImage& trimap) {
  SYLVA_CHECK_INPUT(reference.width() == alpha.width() && reference.height() == alpha.height(),
                    "reference")
      << "has another size than the photo";
  double sum = 0.0, sum_unknown = 0.0;
  int64_t num_unknown = 0;
  for (size_t i = 0; i < alpha.NumPixels(); ++i) {
    const double d = std::abs(alpha.values()[i] - reference.values()[i]);
    sum += d;
    const float t = trimap.empty() ? 0.0f : trimap.values()[i];
    if (t > kTrimapBackgroundMax && t < kTrimapForegroundMin) {
      sum_unknown += d;
      ++num_unknown;
    }
  }
  std::printf("  MAD to reference: %.5f over all %zu pixels, %.5f over %lld unknown pixels\n",
              sum / alpha.NumPixels(), alpha.NumPixels(),
              num_unknown > 0 ? sum_unknown / num_unknown : 0.0,
              static_cast<long long>(num_unknown));
}

// Images side by side (grey ones as RGB), skipping empty ones.
FloatImage SideBySide(const std::vector<FloatImage>& images) {
  int width = 0, height = 0;
  for (const FloatImage& image : images) {
    width += image.width();
    height = std::max(height, image.height());
  }
  FloatImage out(width, height, 3);
  int x0 = 0;
  for (const FloatImage& image : images) {
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) {
        for (int c = 0; c < 3; ++c) {
          out.at(x0 + x, y, c) = image.at(x, y, image.channels() >= 3 ? c : 0);
        }
      }
    }
    x0 += image.width();
  }
  return out;
}

int Main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s PHOTO [--name=value ...] (see the source)\n", argv[0]);
    return 2;
  }
  ProbeFlags flags;
  MattingOptions options;
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    const size_t equals = flag.find('=');
    if (flag.rfind("--", 0) != 0 || equals == std::string::npos ||
        !ApplyFlag(flag.substr(2, equals - 2), flag.substr(equals + 1), &flags, &options)) {
      std::fprintf(stderr, "unknown flag %s\n", flag.c_str());
      return 2;
    }
  }
  const FloatImage photo = DownsampleChannels(ReadImage(argv[1]), flags.scale);
  const FloatImage hint = flags.hint.empty()
                              ? FloatImage()
                              : DownsampleChannels(ReadHintTrimap(flags.hint), flags.scale);
  const FloatImage background = flags.background.empty()
                                    ? FloatImage()
                                    : DownsampleChannels(ReadImage(flags.background), flags.scale);
  MattingSummary summary;
  FloatImage trimap;
  FloatImage alpha;
  if (flags.given_trimap.empty()) {
    alpha = ComputeMatte(photo, hint, background, options, nullptr, &summary);
  } else {
    trimap = DownsampleChannels(ReadMatte(flags.given_trimap), flags.scale);
    const auto start = std::chrono::steady_clock::now();
    alpha = RefineMatte(photo, trimap, options, nullptr, &summary);
    summary.trimap_source = "given";
    summary.seconds_refine = summary.seconds_total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const FloatImage truth = flags.silhouette.empty()
                               ? FloatImage()
                               : DownsampleChannels(ReadMatte(flags.silhouette), flags.scale);
  const SilhouetteScores empty_truth =
      CompareSilhouettes(alpha, FloatImage(alpha.width(), alpha.height(), 1, 0.0f));
  std::printf("%s %dx%d foreground_px %lld", argv[1], photo.width(), photo.height(),
              static_cast<long long>(empty_truth.false_positive));
  if (!truth.empty()) {
    const SilhouetteScores scores = CompareSilhouettes(alpha, truth);
    std::printf(" IoU %.4f precision %.4f recall %.4f", scores.iou, scores.precision,
                scores.recall);
  }
  std::printf("\n  %s\n", summary.BriefReport().c_str());
  const FloatImage reference = flags.reference.empty()
                                   ? FloatImage()
                                   : DownsampleChannels(ReadMatte(flags.reference), flags.scale);
  if (!reference.empty()) ReportDifference(alpha, reference, trimap);
  if (trimap.empty() && (!flags.trimap.empty() || !flags.side_by_side.empty())) {
    trimap = CombineHintTrimap(ComputeTrimap(photo, options, background), hint);
  }
  if (!flags.matte.empty()) WriteImage(flags.matte, alpha);
  if (!flags.trimap.empty()) WriteTrimap(flags.trimap, trimap);
  if (!flags.overlay.empty()) WriteImage(flags.overlay, Overlay(photo, alpha, truth));
  if (!flags.side_by_side.empty()) {
    WriteImage(flags.side_by_side, SideBySide({photo, trimap, alpha, reference}));
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    return sylva::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
