#include "reconstruct/matting/matting.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "reconstruct/matting/trimap.h"

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

// Share of the progress bar given to the trimap (the refinement gets the rest).
constexpr double kTrimapShare = 0.2;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void CountLabels(const FloatImage& trimap, MattingSummary* summary) {
  summary->num_foreground = summary->num_background = summary->num_unknown = 0;
  for (float v : trimap.values()) {
    if (v <= kTrimapBackgroundMax) {
      ++summary->num_background;
    } else if (v >= kTrimapForegroundMin) {
      ++summary->num_foreground;
    } else {
      ++summary->num_unknown;
    }
  }
}

void CheckHint(const FloatImage& hint, int width, int height) {
  if (hint.empty()) return;
  SYLVA_CHECK_INPUT(hint.channels() == 1, "hint trimap")
      << "must have one channel, got " << hint.channels();
  SYLVA_CHECK_INPUT(hint.width() == width && hint.height() == height, "hint trimap")
      << "is " << hint.width() << "x" << hint.height() << " but the photo is " << width << "x"
      << height;
  for (size_t i = 0; i < hint.NumPixels(); ++i) {
    const float h = hint.values()[i];
    SYLVA_CHECK_INPUT(std::isfinite(h) && h >= 0.0f && h <= 1.0f, "hint trimap")
        << "value " << h << " at pixel (" << i % width << ", " << i / width << ") is not in [0, 1]";
  }
}

}  // namespace

std::string MattingSummary::BriefReport() const {
  std::ostringstream out;
  out << "matte: trimap " << trimap_source;
  if (trimap_source == "backdrop" || trimap_source == "grabcut") {
    out << " (border seed RGB " << std::lround(255 * backdrop_rgb[0]) << ","
        << std::lround(255 * backdrop_rgb[1]) << "," << std::lround(255 * backdrop_rgb[2])
        << ", border agreement " << std::lround(100 * border_agreement) << " %)";
  }
  if (hint_used) out << " + painted hint";
  out << "; " << num_foreground << " foreground, " << num_unknown << " unknown, " << num_background
      << " background pixels; refined at 1/" << refine_factor;
  if (solver_iterations > 0) out << " (" << solver_iterations << " CG iterations)";
  out << "; " << seconds_trimap << " s trimap, " << seconds_refine << " s refine, " << seconds_total
      << " s total";
  return out.str();
}

FloatImage CombineHintTrimap(const FloatImage& automatic, const FloatImage& hint) {
  if (hint.empty()) return automatic;
  CheckHint(hint, automatic.width(), automatic.height());
  FloatImage combined = automatic;
  for (size_t i = 0; i < hint.NumPixels(); ++i) {
    const float h = hint.values()[i];
    if (h <= kTrimapBackgroundMax) {
      combined.values()[i] = kTrimapBackground;
    } else if (h >= kTrimapForegroundMin) {
      combined.values()[i] = kTrimapForeground;
    }
  }
  return combined;
}

FloatImage ComputeMatte(const FloatImage& photo, const FloatImage& hint_trimap,
                        const FloatImage& background_photo, const MattingOptions& options,
                        ProgressTask* progress, MattingSummary* summary) {
  const Clock::time_point start = Clock::now();
  options.Check();
  CheckPhotos(photo, background_photo);
  MattingSummary local;
  CheckHint(hint_trimap, photo.width(), photo.height());
  if (progress != nullptr) progress->Update(0.0);
  const FloatImage automatic =
      ComputeAutomaticTrimap(photo, options, background_photo, hint_trimap, &local);
  const FloatImage trimap = CombineHintTrimap(automatic, hint_trimap);
  local.hint_used = !hint_trimap.empty();
  CountLabels(trimap, &local);
  local.seconds_trimap = SecondsSince(start);
  if (progress != nullptr) progress->Update(kTrimapShare);

  const Clock::time_point refine_start = Clock::now();
  FloatImage alpha;
  if (progress != nullptr) {
    ProgressTask refine_task = progress->SubTask("matte: refine", kTrimapShare, 1.0);
    alpha = RefineMatte(photo, trimap, options, &refine_task, &local);
  } else {
    alpha = RefineMatte(photo, trimap, options, nullptr, &local);
  }
  local.seconds_refine = SecondsSince(refine_start);
  local.seconds_total = SecondsSince(start);
  if (progress != nullptr) progress->Update(1.0);
  if (summary != nullptr) *summary = local;
  return alpha;
}

}  // namespace sylva
