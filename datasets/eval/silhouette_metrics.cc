#include "datasets/eval/silhouette_metrics.h"

#include "core/util/check.h"

namespace sylva {
namespace {

double RatioOrOne(int64_t numerator, int64_t denominator) {
  return denominator == 0 ? 1.0 : static_cast<double>(numerator) / denominator;
}

}  // namespace

SilhouetteScores CompareSilhouettes(const FloatImage& predicted, const FloatImage& reference,
                                    float predicted_threshold, float reference_threshold) {
  SYLVA_CHECK(predicted.channels() == 1 && reference.channels() == 1);
  SYLVA_CHECK(predicted.width() == reference.width() && predicted.height() == reference.height())
      << predicted.width() << "x" << predicted.height() << " vs " << reference.width() << "x"
      << reference.height();
  SilhouetteScores scores;
  for (size_t i = 0; i < predicted.NumPixels(); ++i) {
    const bool in_predicted = predicted.data()[i] >= predicted_threshold;
    const bool in_reference = reference.data()[i] >= reference_threshold;
    scores.true_positive += in_predicted && in_reference;
    scores.false_positive += in_predicted && !in_reference;
    scores.false_negative += !in_predicted && in_reference;
  }
  const int64_t tp = scores.true_positive;
  scores.iou = RatioOrOne(tp, tp + scores.false_positive + scores.false_negative);
  scores.precision = RatioOrOne(tp, tp + scores.false_positive);
  scores.recall = RatioOrOne(tp, tp + scores.false_negative);
  return scores;
}

}  // namespace sylva
