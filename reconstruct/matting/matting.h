// The matte stage (thesis 3.2.1): from a photo to a float alpha matte of the
// tree, in two steps.
//
//  1. Trimap: every pixel is labelled background (0), unknown (0.5) or
//     foreground (1). Sources (MattingOptions::trimap):
//       "backdrop"   the tree stands in front of a backdrop (black velvet, a
//                    white cabin, a blue screen). The backdrop's colour is
//                    taken from the photo's border and its shading is
//                    estimated over the whole photo (a smooth "clean plate",
//                    see backdrop.h); a pixel's distance to that clean plate
//                    in chroma and luminance decides its label. This is
//                    colour keying ("blue-screen matting", Smith & Blinn 1996)
//                    with a spatially varying key.
//       "difference" the same test against a photo of the empty scene
//                    ("difference matting" in the thesis).
//       "grabcut"    no backdrop: OpenCV's GrabCut (Rother et al. 2004),
//                    initialised with the photo's border as background.
//       "auto"       "difference" when a background photo is given, else
//                    "backdrop" when the border looks like one backdrop colour,
//                    else "grabcut".
//     Then, for every source: an unknown band of band_px pixels around every
//     foreground/background boundary; and hard background where hues are
//     rejected (orange calibration targets), where pixels are too dark
//     (black cabin fittings) and outside a region of interest (all off by
//     default).
//  2. Refinement: the unknown pixels get a fractional alpha from the colours
//     of the known ones, by information-flow matting (Aksoy et al. 2017,
//     OpenCV's alphamat module) or closed-form matting (Levin et al. 2008,
//     our implementation), at a reduced resolution for large photos and
//     upsampled with a guided filter (He et al. 2013).
//
// A painted hint trimap (the user's PNG in PROJECT/edits/) overrides the
// automatic trimap wherever it is painted; see CombineHintTrimap.
//
// Limits: colour cannot separate what looks like the backdrop. Dark foliage
// on black velvet loses its shadowed inside (the holm-oak cut-out: IoU 0.41
// over black, 0.93 over white; tests/bench/matting_benchmark.cc), green
// over green clutter is lost, cast shadows on a white floor are kept. Use a
// contrasting backdrop, a background photo, or paint hints.
//
// Images: photos are RGB or RGBA FloatImages in [0, 1] (alpha is ignored);
// trimaps and mattes have one channel. Trimap values are read as
// background if <= 0.2, foreground if >= 0.8, unknown otherwise (OpenCV
// alphamat's convention; PNGs store 0 / 128 / 255). Pixel sizes and widths in
// the options are in pixels of the full-resolution photo.
#ifndef SYLVA_RECONSTRUCT_MATTING_MATTING_H_
#define SYLVA_RECONSTRUCT_MATTING_MATTING_H_

#include <array>
#include <cstdint>
#include <string>

#include "core/types/float_image.h"
#include "core/util/progress.h"

namespace sylva {

// Trimap values as written by ComputeTrimap and CombineHintTrimap.
constexpr float kTrimapBackground = 0.0f;
constexpr float kTrimapUnknown = 0.5f;
constexpr float kTrimapForeground = 1.0f;
// Reading thresholds: <= kTrimapBackgroundMax is background,
// >= kTrimapForegroundMin is foreground, anything between is unknown.
constexpr float kTrimapBackgroundMax = 0.2f;
constexpr float kTrimapForegroundMin = 0.8f;

struct MattingOptions {
  // ---- Trimap ----
  // "auto", "backdrop", "difference" or "grabcut" (see the top of this file).
  std::string trimap = "auto";
  // "auto" picks "backdrop" when at least this fraction of the border strip's
  // pixels agree with the strip's median colour (evidence below 1, see
  // backdrop_color); below, "grabcut". Measured: ROMI black velvet 95 %,
  // PhenoArch white cabin 77-86 %, the cluttered OpenCV plant photo 5 %.
  double auto_backdrop_fraction = 0.6;

  // Backdrop colour: "auto" = the per-channel median of the border strip, or
  // "R,G,B" in 0..255. It only seeds the estimate; the clean plate then
  // follows the backdrop's shading across the photo.
  std::string backdrop_color = "auto";
  // Width of the border strip sampled for the backdrop colour, as a fraction
  // of the photo's shorter side (at least 2 pixels).
  double border_fraction = 0.02;
  // Chroma tolerance: the sine of the angle between a pixel's RGB vector and
  // the clean plate's that the backdrop may show (0.12 ~ 7 degrees).
  double chroma_tolerance = 0.12;
  // Luminance tolerance: the absolute difference of mean RGB (in [0, 1]) to
  // the clean plate that the backdrop may show (shading, velvet folds).
  double luminance_tolerance = 0.15;
  // Below this luminance (mean RGB in [0, 1]) a pixel's chroma is mostly
  // noise: its chroma distance is divided by this level instead of by its
  // own brightness.
  double dark_level = 0.1;
  // A pixel's evidence is max(chroma distance / chroma_tolerance, luminance
  // difference / luminance_tolerance): below 1 it is background, at or above
  // foreground_evidence foreground, unknown between (unitless, > 1).
  double foreground_evidence = 2.0;
  // Smoothness of the clean plate: Gaussian sigma as a fraction of the
  // photo's longer side. Larger follows shading less but survives larger
  // foreground objects.
  double backdrop_smoothness = 0.03;

  // Unknown band: pixels within band_px pixels of both a foreground and a
  // background pixel become unknown (so thin structures keep their core).
  int band_px = 1;

  // Hue ranges that are never foreground, in degrees on the HSV wheel: ""
  // (none, the default) or "lo-hi[,lo-hi...]" with 0 <= lo, hi <= 360; a
  // range with lo > hi wraps through 0 ("330-30" is red to orange). Pixels
  // in a range at least reject_min_saturation saturated (HSV S) and
  // reject_min_value bright (HSV V) form the rejected objects, if they are at
  // least reject_min_width_px wide (pixels; thinner structures of those hues
  // such as tan stems, or the orange-tinged edges of stems over black, are
  // kept); less saturated pixels of the same hues (0.6 x) within 3 pixels
  // join them (highlights), holes of a few pixels are filled, and a margin of
  // reject_margin_px pixels around them (their blended edges) is rejected too.
  // For the orange calibration targets and clips of ROMI scans and the
  // orange frame of the PhenoArch cabin: "330-35". (ROMI's tan stems reach
  // hue 37 and saturation 0.45 and its over-exposed targets hue 28-32 at
  // saturation 0.44-0.49: 0.45 keeps 98 % of the stems' cores and rejects
  // 99 % of the strongly orange pixels; 0.35 would also reject the brown
  // support rod but with it the stem where it runs along the rod.)
  std::string reject_hues;
  double reject_min_saturation = 0.45;
  double reject_min_value = 0.15;
  int reject_min_width_px = 7;
  int reject_margin_px = 2;
  // Pixels darker than this HSV value (max of R, G, B in [0, 1]) are never
  // foreground either (with the same fringe, hole and margin treatment): the
  // black rails and pot holders of a white cabin. 0 (the default) = off. It
  // cannot be used on dark backdrops' photos of dark plants, obviously.
  double reject_below_value = 0.0;

  // Region of interest "x0,y0,x1,y1" as fractions of the photo's width and
  // height (0,0 = top left): everything outside is background. "" (the
  // default) = the whole photo. For fixed cabins whose fittings (pot holder,
  // rails, lamps) would otherwise be foreground.
  std::string region;

  // GrabCut: iterations, and the border strip assumed background as a
  // fraction of each side. GrabCut runs at most at grabcut_max_megapixels
  // (the photo is box-downsampled by an integer factor above).
  int grabcut_iterations = 5;
  double grabcut_margin = 0.05;
  double grabcut_max_megapixels = 0.3;

  // ---- Refinement ----
  // "closed_form" (Levin et al. 2008, our sparse solver over the unknown
  // pixels only; the default, see the report in matting_benchmark.cc),
  // "alphamat" (information flow, cv::alphamat::infoFlow, on the bounding box
  // of the unknown pixels) or "none" (unknown pixels get alpha 0.5).
  std::string refine = "closed_form";
  // Refinement runs on the photo box-downsampled by an integer factor so that
  // it has at most this many megapixels; the alpha is then upsampled guided
  // by the full-resolution photo (fast guided filter). Known trimap pixels
  // always keep alpha exactly 0 or 1. Closed form costs what the unknown band
  // costs, so 2 MP keeps 1.7-MP scans (ROMI) at full resolution for their
  // thin stems; information flow costs what the bounding box of the unknown
  // pixels costs (about 30 s per megapixel): lower this for it.
  double max_megapixels = 2.0;
  // Closed-form matting: the regulariser epsilon of the local colour-line
  // model (colours in [0, 1]), the conjugate-gradient limits, and the weight
  // of a weak pull towards alpha 0.5 that keeps unknown regions with no known
  // neighbour well-posed.
  double closed_form_epsilon = 1e-5;
  int closed_form_max_iterations = 2000;
  double closed_form_tolerance = 1e-6;
  double closed_form_prior_weight = 1e-6;
  // Guided upsampling: window radius (pixels of the reduced image) and
  // regulariser (colours in [0, 1]).
  int upsample_radius = 2;
  double upsample_epsilon = 1e-4;

  // Seed of GrabCut's k-means initialisation (the only random step).
  int seed = 1;

  // Throws InputError naming the first violated constraint
  // ("Matting.band_px must be ...").
  void Check() const;
};

// What ComputeMatte did, for logs and reports.
struct MattingSummary {
  std::string trimap_source;                       // "backdrop", "difference", "grabcut"
  std::array<double, 3> backdrop_rgb = {0, 0, 0};  // seed colour in [0, 1] (backdrop only)
  double border_agreement = 0.0;  // fraction of border pixels matching backdrop_rgb
  bool hint_used = false;
  int64_t num_foreground = 0, num_background = 0, num_unknown = 0;  // final trimap
  int refine_factor = 1;      // integer downsampling factor of the refinement
  int solver_iterations = 0;  // closed-form conjugate gradient
  double seconds_trimap = 0, seconds_refine = 0, seconds_total = 0;

  std::string BriefReport() const;
};

// The automatic trimap of `photo` (see the top of this file).
// `background_photo`, if not empty, is a photo of the empty scene of the same
// size (RGB or RGBA). Throws InputError for bad images or options.
FloatImage ComputeTrimap(const FloatImage& photo, const MattingOptions& options,
                         const FloatImage& background_photo = {});

// Refines a trimap into an alpha matte (one channel, [0, 1]). Known trimap
// pixels keep alpha 0 or 1 exactly. Throws InputError naming "trimap" if it is
// not one channel of the photo's size with finite values in [0, 1].
FloatImage RefineMatte(const FloatImage& photo, const FloatImage& trimap,
                       const MattingOptions& options, ProgressTask* progress = nullptr,
                       MattingSummary* summary = nullptr);

// How a painted hint combines with the automatic trimap, pixel by pixel:
// where the hint is background (<= 0.2) or foreground (>= 0.8) the result
// takes the hint's label; where it is unknown (0.5, i.e. unpainted, see
// ReadHintTrimap) the automatic label stays. No unknown band is added along
// painted edges: a painted boundary is taken as drawn. An empty hint returns
// `automatic` unchanged. Throws InputError naming "hint trimap" for a wrong
// size or values.
FloatImage CombineHintTrimap(const FloatImage& automatic, const FloatImage& hint);

// The full matte: the automatic trimap (GrabCut also learns from the hint's
// painted pixels), combined with `hint_trimap` (may be empty), refined.
// `background_photo` may be empty. `progress` may be null; throws Cancelled
// when it asks to stop.
FloatImage ComputeMatte(const FloatImage& photo, const FloatImage& hint_trimap,
                        const FloatImage& background_photo, const MattingOptions& options,
                        ProgressTask* progress = nullptr, MattingSummary* summary = nullptr);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_MATTING_H_
