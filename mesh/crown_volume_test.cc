#include "mesh/crown_volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "core/geometry/box.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "datasets/synthetic/synthetic_tree.h"

namespace sylva {
namespace {

// The closing scale of a 6 m tree (TreeMetricsOptions: 3 % of the height).
constexpr double kScale = 0.03 * 6.0;

CrownVolumeOptions WithScale(double scale) {
  CrownVolumeOptions options;
  options.scale = scale;
  return options;
}

// A grid whose voxels (centres at (i + 1/2) h, so faces lie at multiples of
// h) hold the opacity of the extinction field `sigma` (per metre) averaged
// over n^3 points per voxel, as a reconstruction blurs edges, over `box`;
// `keep(ijk)` may drop voxels (holes).
DensityGrid RasterizeExtinction(
    double voxel_size, const Box3d& box, int n,
    const std::function<double(const Eigen::Vector3d&)>& sigma,
    const std::function<bool(const Eigen::Vector3i&)>& keep = [](const Eigen::Vector3i&) {
      return true;
    }) {
  DensityGrid grid(voxel_size, Eigen::Vector3d::Constant(0.5 * voxel_size));
  const Eigen::Vector3i lo = (box.min() / voxel_size).array().floor().cast<int>();
  const Eigen::Vector3i hi = (box.max() / voxel_size).array().ceil().cast<int>();
  for (int k = lo.z(); k < hi.z(); ++k) {
    for (int j = lo.y(); j < hi.y(); ++j) {
      for (int i = lo.x(); i < hi.x(); ++i) {
        if (!keep({i, j, k})) continue;
        double sum = 0.0;
        for (int c = 0; c < n * n * n; ++c) {
          const Eigen::Vector3d sub((c % n + 0.5) / n, (c / n % n + 0.5) / n,
                                    (c / n / n + 0.5) / n);
          sum += sigma(voxel_size * (Eigen::Vector3d(i, j, k) + sub));
        }
        const double optical_depth = voxel_size * sum / (n * n * n);
        if (optical_depth > 0) grid.SetValue({i, j, k}, 1.0 - std::exp(-optical_depth));
      }
    }
  }
  return grid;
}

// Adds `count` faint voxels (extinction uniform in [0.01, 1] x max_sigma)
// at random empty places in `box`.
void AddFaintNoise(const Box3d& box, int count, double max_sigma, uint64_t seed,
                   DensityGrid* grid) {
  RandomEngine random(seed);
  const double h = grid->voxel_size();
  for (int added = 0; added < count;) {
    const Eigen::Vector3d p(random.Uniform(box.min().x(), box.max().x()),
                            random.Uniform(box.min().y(), box.max().y()),
                            random.Uniform(box.min().z(), box.max().z()));
    const Eigen::Vector3i ijk = (p / h).array().floor().cast<int>();
    if (grid->Value(ijk) > 0) continue;
    grid->SetValue(ijk, 1.0 - std::exp(-h * random.Uniform(0.01, 1.0) * max_sigma));
    ++added;
  }
}

// An ellipsoid with semi-axes 1.6, 1.2, 0.9 m.
struct Ellipsoid {
  Eigen::Vector3d centre = Eigen::Vector3d(0.3, -0.2, 3.0);
  Eigen::Vector3d semi = Eigen::Vector3d(1.6, 1.2, 0.9);

  double Volume() const { return 4.0 / 3.0 * M_PI * semi.prod(); }
  // Inside, scaled by `factor` about the centre.
  bool Contains(const Eigen::Vector3d& p, double factor = 1.0) const {
    return ((p - centre).array() / (factor * semi).array()).matrix().squaredNorm() <= 1.0;
  }
  Box3d Bounds() const { return Box3d(centre - semi, centre + semi); }
};

TEST(CrownVolumeTest, UniformEllipsoidAtAnyResolutionAndDensityIsFourThirdsPiAbc) {
  const Ellipsoid e;
  for (double voxel_size : {0.1, 0.05}) {
    for (double sigma : {0.5, 4.0}) {  // per metre: see-through, and nearly opaque per 10 cm
      SCOPED_TRACE(testing::Message() << "voxel " << voxel_size << " sigma " << sigma);
      DensityGrid grid = RasterizeExtinction(
          voxel_size, e.Bounds(), 4,
          [&](const Eigen::Vector3d& p) { return e.Contains(p) ? sigma : 0.0; });
      // Twice as many faint voxels as the ellipsoid has, below the support
      // fraction (5 %) of its extinction, around it.
      const Box3d around(e.centre - 2 * e.semi, e.centre + 2 * e.semi);
      AddFaintNoise(around, 2 * static_cast<int>(grid.NumActiveVoxels()), 0.045 * sigma, 7, &grid);
      const double volume = DensityCrownVolume(grid, -100.0, WithScale(kScale));
      // A crown base through the centre (a voxel face) keeps the upper half.
      const double upper = DensityCrownVolume(grid, e.centre.z(), WithScale(kScale));
      std::printf("voxel %.2f sigma %.1f: %.4f of 4/3 pi abc, upper half %.4f\n", voxel_size, sigma,
                  volume / e.Volume(), upper / (0.5 * e.Volume()));
      EXPECT_NEAR(volume, e.Volume(), 0.01 * e.Volume());
      EXPECT_NEAR(upper, 0.5 * e.Volume(), 0.01 * e.Volume());
      // Without closing, the same (no gaps to close).
      EXPECT_NEAR(DensityCrownVolume(grid, -100.0, WithScale(0.0)), e.Volume(), 0.01 * e.Volume());
    }
  }
}

TEST(CrownVolumeTest, GapsNarrowerThanTheScaleAndAHollowInsideAreCrown) {
  // A see-through crown: the ellipsoid with 30 % of its voxels empty (a
  // finer grid resolves finer gaps: the same volume at both resolutions),
  // and a hollow one (a shell 0.25 of the semi-axes thick).
  const Ellipsoid e;
  for (double voxel_size : {0.1, 0.05}) {
    SCOPED_TRACE(voxel_size);
    RandomEngine random(5);
    const DensityGrid porous = RasterizeExtinction(
        voxel_size, e.Bounds(), 2,
        [&](const Eigen::Vector3d& p) { return e.Contains(p) ? 1.0 : 0.0; },
        [&](const Eigen::Vector3i&) { return random.Uniform() >= 0.3; });
    const double closed = DensityCrownVolume(porous, -100.0, WithScale(kScale));
    const double open = DensityCrownVolume(porous, -100.0, WithScale(0.0));
    std::printf("voxel %.2f: porous %.4f of 4/3 pi abc closed, %.4f open\n", voxel_size,
                closed / e.Volume(), open / e.Volume());
    // The pores open to the outside lower the surface layer's share.
    EXPECT_NEAR(closed, e.Volume(), 0.05 * e.Volume());
    // The density's own support (enclosed pores filled) misses the open ones.
    EXPECT_LT(open, 0.9 * closed);
    const DensityGrid hollow =
        RasterizeExtinction(voxel_size, e.Bounds(), 2, [&](const Eigen::Vector3d& p) {
          return e.Contains(p) && !e.Contains(p, 0.75) ? 2.0 : 0.0;
        });
    EXPECT_NEAR(DensityCrownVolume(hollow, -100.0, WithScale(kScale)), e.Volume(),
                0.02 * e.Volume());
  }
}

// The leaf clusters as a density grid: each cluster's ellipsoid with its
// extinction `sigmas[k]` (overlaps add), averaged over n^3 points per voxel;
// voxel faces at multiples of `voxel_size`.
DensityGrid RasterizeClusters(const std::vector<SyntheticLeafCluster>& clusters,
                              const std::vector<double>& sigmas, double voxel_size, int n) {
  std::map<std::tuple<int, int, int>, double> depth;  // optical depth per voxel
  for (size_t k = 0; k < clusters.size(); ++k) {
    const SyntheticLeafCluster& c = clusters[k];
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(std::max(c.along, c.across));
    const Eigen::Vector3i lo = ((c.centre - r) / voxel_size).array().floor().cast<int>();
    const Eigen::Vector3i hi = ((c.centre + r) / voxel_size).array().ceil().cast<int>();
    for (int z = lo.z(); z < hi.z(); ++z) {
      for (int y = lo.y(); y < hi.y(); ++y) {
        for (int x = lo.x(); x < hi.x(); ++x) {
          int inside = 0;
          for (int s = 0; s < n * n * n; ++s) {
            const Eigen::Vector3d sub((s % n + 0.5) / n, (s / n % n + 0.5) / n,
                                      (s / n / n + 0.5) / n);
            inside += c.Contains(voxel_size * (Eigen::Vector3d(x, y, z) + sub));
          }
          if (inside > 0) depth[{x, y, z}] += voxel_size * sigmas[k] * inside / (n * n * n);
        }
      }
    }
  }
  DensityGrid grid(voxel_size, Eigen::Vector3d::Constant(0.5 * voxel_size));
  for (const auto& [xyz, d] : depth) {
    grid.SetValue({std::get<0>(xyz), std::get<1>(xyz), std::get<2>(xyz)}, 1.0 - std::exp(-d));
  }
  return grid;
}

TEST(CrownVolumeTest, SyntheticTreeLeafClustersGiveTheirUnionAtTwoResolutions) {
  // The synthetic tree's crown as a density: each leaf cluster's ellipsoid
  // holding the extinction of its leaves (mean leaf area x leaves / cluster
  // volume / 2, randomly oriented leaves), so smaller clusters are denser
  // and overlaps add (5x between the sparsest and the densest cluster,
  // more where they overlap); the branches left out. The crown region is
  // the clusters' union; without closing (scale 0) that is what counts.
  const SyntheticTreeOptions options;
  const SyntheticTree tree = GenerateSyntheticTree(options, 4);
  const double lo = options.leaf_length_min, hi = options.leaf_length_max;
  const double mean_area =  // rhombus l x aspect l / 2, l uniform in [lo, hi]
      0.5 * options.leaf_aspect * (hi * hi * hi - lo * lo * lo) / (3 * (hi - lo));
  std::vector<double> sigmas;
  for (const SyntheticLeafCluster& c : tree.clusters) {
    sigmas.push_back(0.5 * options.leaves_per_cluster * mean_area / c.Volume());
  }
  const double exact = LeafClustersUnionVolume(tree.clusters, 4000, 3);
  const double tolerance[] = {0.07, 0.03};
  int k = 0;
  for (double voxel_size : {0.1, 0.05}) {
    const DensityGrid grid = RasterizeClusters(tree.clusters, sigmas, voxel_size, 3);
    const double volume = DensityCrownVolume(grid, -100.0, WithScale(0.0));
    const double closed = DensityCrownVolume(grid, -100.0, WithScale(kScale));
    std::printf("voxel %.2f: %.3f m^3 (closed: %.3f), union of the clusters %.3f m^3 (%.4f)\n",
                voxel_size, volume, closed, exact, volume / exact);
    EXPECT_NEAR(volume, exact, tolerance[k++] * exact) << voxel_size;
    // Closing only adds the gaps between clusters.
    EXPECT_GE(closed, volume);
  }
}

TEST(CrownVolumeTest, CountsOnlyAboveTheCrownBaseAndChecksItsOptions) {
  const Ellipsoid e;
  const DensityGrid grid = RasterizeExtinction(
      0.1, e.Bounds(), 2, [&](const Eigen::Vector3d& p) { return e.Contains(p) ? 1.0 : 0.0; });
  EXPECT_EQ(DensityCrownVolume(grid, e.centre.z() + 1.0, CrownVolumeOptions()), 0.0);
  EXPECT_EQ(
      DensityCrownVolume(DensityGrid(0.1, Eigen::Vector3d::Zero()), 0.0, CrownVolumeOptions()),
      0.0);
  CrownVolumeOptions options;
  options.scale = -1;
  EXPECT_THROW(DensityCrownVolume(grid, 0.0, options), InputError);
  options = CrownVolumeOptions();
  options.support_fraction = 0;
  EXPECT_THROW(DensityCrownVolume(grid, 0.0, options), InputError);
}

}  // namespace
}  // namespace sylva
