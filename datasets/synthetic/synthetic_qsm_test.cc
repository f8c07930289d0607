#include "datasets/synthetic/synthetic_qsm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/util/check.h"

namespace sylva {
namespace {

int Roots(const QsmModel& qsm) {
  return static_cast<int>(std::count_if(qsm.cylinders.begin(), qsm.cylinders.end(),
                                        [](const QsmCylinder& c) { return c.parent_id == 0; }));
}

// Laser-scan-like: thousands of cylinders, the trunk plus the detached
// fragments as roots, twigs down to 1 mm radius, parents before children,
// cylinders a few radii long; the same seed gives the same table.
TEST(SyntheticQsmTest, ThousandsOfShortNoisyCylindersWithFragments) {
  const SyntheticQsmOptions options;
  const QsmModel qsm = GenerateSyntheticQsm(options, 1);
  const int n = static_cast<int>(qsm.cylinders.size());
  double thinnest = 1e300, thickest = 0.0;
  int thin = 0;
  for (int k = 0; k < n; ++k) {
    const QsmCylinder& c = qsm.cylinders[k];
    EXPECT_EQ(c.id, k + 1);
    EXPECT_LT(c.parent_id, c.id);
    thinnest = std::min(thinnest, c.radius);
    thickest = std::max(thickest, c.radius);
    thin += c.radius < 0.0025 ? 1 : 0;
    EXPECT_LE(c.length, options.max_cylinder_length * 1.6) << c.id;
  }
  std::printf("seed 1: %d cylinders, %d roots, radii %.4f-%.4f m, %d under 2.5 mm\n", n, Roots(qsm),
              thinnest, thickest, thin);
  EXPECT_GE(n, 3000);
  EXPECT_LE(n, 20000);
  EXPECT_EQ(Roots(qsm), 1 + options.fragments);
  EXPECT_NEAR(thinnest, 0.001, 1e-4);
  EXPECT_GT(thin, n / 10);
  EXPECT_NEAR(thickest, options.tree.trunk_base_radius, 0.2 * options.tree.trunk_base_radius);

  const QsmModel again = GenerateSyntheticQsm(options, 1);
  ASSERT_EQ(again.cylinders.size(), qsm.cylinders.size());
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(again.cylinders[k].start, qsm.cylinders[k].start);
    EXPECT_EQ(again.cylinders[k].radius, qsm.cylinders[k].radius);
  }
  EXPECT_NE(GenerateSyntheticQsm(options, 2).cylinders.size(), qsm.cylinders.size());

  // The overlaps are small: the union holds most of the cylinders' sum.
  const double sum = QsmCylinderVolumeSum(qsm);
  const double united = QsmUnionVolume(qsm, 64, 1);
  std::printf("seed 1: cylinder volume sum %.5f m^3, union %.5f m^3\n", sum, united);
  EXPECT_LT(united, sum);
  EXPECT_GT(united, 0.85 * sum);
}

TEST(SyntheticQsmTest, RejectsBadOptions) {
  SyntheticQsmOptions options;
  options.min_cylinder_length = 2 * options.max_cylinder_length;
  EXPECT_THROW(GenerateSyntheticQsm(options, 1), InputError);
  options = SyntheticQsmOptions();
  options.radius_noise = 1.0;
  EXPECT_THROW(GenerateSyntheticQsm(options, 1), InputError);
  options = SyntheticQsmOptions();
  options.fragments = -1;
  EXPECT_THROW(GenerateSyntheticQsm(options, 1), InputError);
}

}  // namespace
}  // namespace sylva
