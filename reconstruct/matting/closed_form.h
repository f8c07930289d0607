// Closed-form matting (Levin, Lischinski, Weiss: "A Closed-Form Solution to
// Natural Image Matting", PAMI 2008), solved over the unknown pixels only.
//
// In every 3x3 window w the alpha is assumed an affine function of the colour
// (the colour-line model); eliminating the affine coefficients gives the
// matting Laplacian (eq. 12 of the paper)
//   L_ij = sum_{w containing i, j} ( delta_ij - (1 + (I_i - mu_w)^T
//          (Sigma_w + epsilon / 9 I_3)^{-1} (I_j - mu_w)) / 9 ),
// and alpha minimises alpha^T L alpha with the trimap's known pixels fixed:
//   (L_UU + lambda I) alpha_U = -L_UK alpha_K + lambda 0.5,
// where U are the unknown pixels, K the known ones and lambda a tiny weight
// (prior_weight) that keeps unknown regions without known neighbours
// well-posed. Only windows that touch an unknown pixel are visited, so the
// cost follows the size of the unknown band, not of the photo. The system is
// solved by conjugate gradients with a Jacobi preconditioner.
#ifndef SYLVA_RECONSTRUCT_MATTING_CLOSED_FORM_H_
#define SYLVA_RECONSTRUCT_MATTING_CLOSED_FORM_H_

#include <cstdint>

#include "core/types/float_image.h"
#include "core/util/progress.h"

namespace sylva {

struct ClosedFormOptions {
  double epsilon = 1e-5;       // colour-line regulariser (colours in [0, 1])
  int max_iterations = 2000;   // conjugate-gradient iterations
  double tolerance = 1e-6;     // stop at |residual| <= tolerance |rhs|
  double prior_weight = 1e-6;  // lambda above
};

struct ClosedFormSummary {
  int64_t num_unknown = 0;
  int iterations = 0;
  double relative_residual = 0.0;
};

// `photo`: RGB or RGBA in [0, 1]; `trimap`: one channel, classified with the
// thresholds of matting.h. Returns alpha in [0, 1]; known pixels keep 0 or 1.
FloatImage ClosedFormMatte(const FloatImage& photo, const FloatImage& trimap,
                           const ClosedFormOptions& options, ProgressTask* progress,
                           ClosedFormSummary* summary);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_CLOSED_FORM_H_
