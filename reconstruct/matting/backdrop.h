// Backdrop keying for the "backdrop" and "difference" trimaps (internal to
// reconstruct/matting; includes OpenCV). Images are CV_32FC3 RGB in [0, 1].
//
// A pixel p is compared with the backdrop colour b behind it (the "clean
// plate") by its evidence of being foreground,
//   E = max(chroma(p, b) / chroma_tolerance, |lum(p) - lum(b)| / luminance_tolerance),
// where lum is the mean of R, G, B and chroma is the sine of the angle
// between the RGB vectors p and b, measured as |p - (p.b^) b^| / max(|p|,
// dark_level sqrt(3)) so that the noisy chroma of dark pixels counts less.
// E < 1: background; E >= foreground_evidence: foreground; unknown between.
//
// The clean plate is the background photo ("difference"), or estimated
// ("backdrop"): the seed colour (the border's per-channel median, or
// MattingOptions::backdrop_color) selects pixels of similar chroma and of
// luminance within the border's range; the plate is their Gaussian-weighted
// average (normalised convolution, sigma = backdrop_smoothness x the longer
// side); then, three times, the pixels with E < 1 against that plate are
// re-selected and the plate re-averaged. It follows slow shading (cabin
// walls, velvet folds) while thin foreground drops out of the average.
#ifndef SYLVA_RECONSTRUCT_MATTING_BACKDROP_H_
#define SYLVA_RECONSTRUCT_MATTING_BACKDROP_H_

#include <opencv2/core.hpp>

#include <array>

#include "reconstruct/matting/matting.h"

namespace sylva {

struct BackdropKey {
  std::array<double, 3> seed_rgb = {0, 0, 0};  // in [0, 1]
  // Fraction of the border strip's pixels with E < 1 against seed_rgb.
  double border_agreement = 0.0;
};

// The seed colour and how well it explains the photo's border.
BackdropKey EstimateBackdropKey(const cv::Mat& rgb, const MattingOptions& options);

// Per-pixel evidence E (CV_32F) against the estimated clean plate, or
// against `background_rgb` if it is not empty.
cv::Mat BackdropEvidence(const cv::Mat& rgb, const MattingOptions& options, const BackdropKey& key,
                         const cv::Mat& background_rgb);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_BACKDROP_H_
