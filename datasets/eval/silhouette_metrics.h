// Silhouette fidelity: how well a predicted opacity image matches a reference
// matte (thesis 7.2.2 uses precision and recall of silhouettes). Both images
// are thresholded; a pixel is foreground if its value >= the threshold.
#ifndef SYLVA_DATASETS_EVAL_SILHOUETTE_METRICS_H_
#define SYLVA_DATASETS_EVAL_SILHOUETTE_METRICS_H_

#include <cstdint>

#include "core/types/float_image.h"

namespace sylva {

struct SilhouetteScores {
  int64_t true_positive = 0;   // foreground in both
  int64_t false_positive = 0;  // predicted only
  int64_t false_negative = 0;  // reference only
  // Intersection over union. 1 when both silhouettes are empty.
  double iou = 1.0;
  // Fraction of predicted foreground that is reference foreground; 1 when
  // nothing is predicted.
  double precision = 1.0;
  // Fraction of reference foreground that is predicted; 1 when the
  // reference is empty.
  double recall = 1.0;
};

// Images must be single-channel and the same size (checked).
SilhouetteScores CompareSilhouettes(const FloatImage& predicted, const FloatImage& reference,
                                    float predicted_threshold = 0.5f,
                                    float reference_threshold = 0.5f);

}  // namespace sylva

#endif  // SYLVA_DATASETS_EVAL_SILHOUETTE_METRICS_H_
