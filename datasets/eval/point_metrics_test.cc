#include "datasets/eval/point_metrics.h"

#include <gtest/gtest.h>

#include "core/util/random.h"

namespace sylva {
namespace {

TEST(PointMetricsTest, MatchesBruteForce) {
  RandomEngine rng(11);
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 300; ++i) a.emplace_back(rng.Uniform(), rng.Uniform(), rng.Uniform() * 3);
  for (int i = 0; i < 200; ++i) b.emplace_back(rng.Uniform(), rng.Normal(), rng.Uniform());
  b.emplace_back(40, 40, 40);  // a far outlier
  double sum_ab = 0, sum_ba = 0, hausdorff = 0;
  for (const auto& p : a) {
    double best = 1e30;
    for (const auto& q : b) best = std::min(best, (p - q).norm());
    sum_ab += best;
    hausdorff = std::max(hausdorff, best);
  }
  for (const auto& q : b) {
    double best = 1e30;
    for (const auto& p : a) best = std::min(best, (p - q).norm());
    sum_ba += best;
    hausdorff = std::max(hausdorff, best);
  }
  const PointSetDistances d = ComparePointSets(a, b);
  EXPECT_NEAR(d.mean_a_to_b, sum_ab / a.size(), 1e-12);
  EXPECT_NEAR(d.mean_b_to_a, sum_ba / b.size(), 1e-12);
  EXPECT_NEAR(d.hausdorff, hausdorff, 1e-12);
  EXPECT_NEAR(d.chamfer, 0.5 * (sum_ab / a.size() + sum_ba / b.size()), 1e-12);
}

TEST(PointMetricsTest, IdenticalSetsHaveZeroDistance) {
  const std::vector<Eigen::Vector3d> a = {{0, 0, 0}, {1, 2, 3}};
  const PointSetDistances d = ComparePointSets(a, a);
  EXPECT_EQ(d.chamfer, 0.0);
  EXPECT_EQ(d.hausdorff, 0.0);
}

}  // namespace
}  // namespace sylva
