#include "datasets/eval/silhouette_metrics.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(SilhouetteMetricsTest, CountsAndScores) {
  FloatImage predicted(4, 1, 1), reference(4, 1, 1);
  // pixel:      0    1    2    3
  // predicted:  1    1    0    0.2
  // reference:  1    0    1    0
  predicted.at(0, 0) = 1.0f;
  predicted.at(1, 0) = 0.9f;
  predicted.at(3, 0) = 0.2f;
  reference.at(0, 0) = 1.0f;
  reference.at(2, 0) = 0.6f;
  const SilhouetteScores s = CompareSilhouettes(predicted, reference);
  EXPECT_EQ(s.true_positive, 1);
  EXPECT_EQ(s.false_positive, 1);
  EXPECT_EQ(s.false_negative, 1);
  EXPECT_DOUBLE_EQ(s.iou, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
}

TEST(SilhouetteMetricsTest, EmptyCasesAndSizeMismatch) {
  FloatImage empty(3, 3, 1), full(3, 3, 1, 1.0f);
  EXPECT_DOUBLE_EQ(CompareSilhouettes(empty, empty).iou, 1.0);
  const SilhouetteScores nothing_predicted = CompareSilhouettes(empty, full);
  EXPECT_DOUBLE_EQ(nothing_predicted.iou, 0.0);
  EXPECT_DOUBLE_EQ(nothing_predicted.precision, 1.0);
  EXPECT_DOUBLE_EQ(nothing_predicted.recall, 0.0);
  EXPECT_THROW(CompareSilhouettes(FloatImage(2, 2, 1), FloatImage(3, 2, 1)), Error);
}

}  // namespace
}  // namespace sylva
