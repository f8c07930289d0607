// Small tools around mattes: compositing a cut-out over a background, a
// trimap from a known alpha, and alpha errors. Used by the matting tests and
// benchmark (ground truth from cut-outs) and by reports (pictures).
#ifndef SYLVA_RECONSTRUCT_MATTING_MATTE_TOOLS_H_
#define SYLVA_RECONSTRUCT_MATTING_MATTE_TOOLS_H_

#include "core/types/float_image.h"

namespace sylva {

// `cutout` is grey+alpha (2 channels) or RGBA with straight alpha;
// `background` RGB(A) of at least the cut-out's size (its top-left part is
// used). Returns the RGB image alpha F + (1 - alpha) B (Porter & Duff "over").
FloatImage CompositeOver(const FloatImage& cutout, const FloatImage& background);

// The cut-out on a transparent canvas `margin` pixels larger on every side
// (a photo whose border shows the backdrop, as real photos do).
FloatImage PadCutout(const FloatImage& cutout, int margin);

// The alpha channel of a grey+alpha or RGBA cut-out.
FloatImage AlphaOf(const FloatImage& cutout);

// A trimap from a known alpha: foreground where alpha >= 1 - tolerance and
// background where alpha <= tolerance, both eroded by `radius` pixels (a
// disk); unknown elsewhere. radius = 0 keeps every pure pixel known.
FloatImage TrimapFromAlpha(const FloatImage& alpha, int radius, float tolerance = 0.02f);

// Box-downsamples every channel by an integer factor (DownsampleBox per
// channel); factor 1 returns the image.
FloatImage DownsampleChannels(const FloatImage& image, int factor);

// `image` repeated with mirroring to cover width x height (its first three
// channels): a cluttered background of any size from a photo.
FloatImage TileMirrored(const FloatImage& image, int width, int height);

struct MatteErrors {
  double sad = 0.0;  // sum of absolute differences (alpha units)
  double mse = 0.0;  // mean squared difference
  double mad = 0.0;  // mean absolute difference
};

// Differences of two single-channel mattes of the same size (checked).
MatteErrors CompareMattes(const FloatImage& matte, const FloatImage& reference);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_MATTE_TOOLS_H_
