#include "reconstruct/density/view_consensus.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/util/check.h"
#include "core/util/statistics.h"
#include "reconstruct/density/view_sampling.h"

namespace sylva {
namespace {

// A mask with less than 1 / this of the median view's foreground would carve
// nearly everything away on its own.
constexpr double kSparseForegroundRatio = 10.0;
// Masks are compared with the consensus hull's projection at about this many
// pixels per voxel of the coarse grid.
constexpr double kComparePixelsPerVoxel = 2.0;

double ForegroundShare(const FloatImage& mask) {
  double sum = 0.0;
  for (float value : mask.values()) sum += value;
  return mask.NumPixels() > 0 ? sum / static_cast<double>(mask.NumPixels()) : 0.0;
}

std::string Percent(double share) {
  std::ostringstream out;
  out << std::setprecision(3) << 100.0 * share << " %";
  return out.str();
}

VoxelBlock CoarseBlock(const Box3d& bounds, int resolution) {
  VoxelBlock block;
  block.voxel_size = bounds.sizes().maxCoeff() / resolution;
  block.lower_corner = bounds.min();
  for (int a = 0; a < 3; ++a) {
    block.dims[a] = std::max(1, static_cast<int>(std::ceil(bounds.sizes()[a] / block.voxel_size)));
  }
  return block;
}

// The consensus hull: voxels seen by at least one view and carved away by at
// most `allowed` of the views that see them.
std::vector<char> ConsensusHull(const FootprintVotes& votes, int allowed, int64_t* count) {
  std::vector<char> hull(votes.seen.size(), 0);
  *count = 0;
  for (size_t i = 0; i < hull.size(); ++i) {
    if (votes.seen[i] > 0 && votes.vetoes[i] <= allowed) {
      hull[i] = 1;
      ++*count;
    }
  }
  return hull;
}

// Share of the mask's foreground that no voxel of the hull projects onto:
// foreground the other views cannot explain (an inverted matte's room). The
// mask is compared at about two pixels per voxel of the coarse grid.
double UnexplainedShare(const ImageSet& image_set, const FloatImage& mask, int v,
                        const VoxelBlock& block, const std::vector<char>& hull) {
  const Eigen::Vector3d center =
      block.lower_corner + 0.5 * block.voxel_size * block.dims.cast<double>();
  const ViewSampling sampling =
      MakeViewSampling(image_set, v, center, block.voxel_size, kComparePixelsPerVoxel, 1);
  const FloatImage small = DownsampleBox(mask, sampling.factor);
  FloatImage covered(small.width(), small.height(), 1, 0.0f);
  const ViewProjector projector(image_set, v);
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    if (!hull[i]) continue;
    const Eigen::Vector3d lower =
        block.lower_corner + block.voxel_size * block.VoxelFromLinear(i).cast<double>();
    Eigen::AlignedBox2d rect;
    if (!projector.ProjectCube(lower, block.voxel_size, &rect)) continue;
    // In downsampled pixels, clamped before the conversion (a corner just in
    // front of a pinhole projects arbitrarily far out).
    const auto pixel_of = [](double coordinate, int size) {
      return static_cast<int>(std::clamp(coordinate, -1.0, size + 1.0));
    };
    const Eigen::AlignedBox2d small_rect(rect.min() / sampling.factor,
                                         rect.max() / sampling.factor);
    const int x0 = std::max(0, pixel_of(std::floor(small_rect.min().x()), small.width()));
    const int y0 = std::max(0, pixel_of(std::floor(small_rect.min().y()), small.height()));
    const int x1 =
        std::min(small.width(), pixel_of(std::ceil(small_rect.max().x()), small.width()));
    const int y1 =
        std::min(small.height(), pixel_of(std::ceil(small_rect.max().y()), small.height()));
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) covered.at(x, y) = 1.0f;
    }
  }
  double foreground = 0.0, unexplained = 0.0;
  for (size_t p = 0; p < small.NumPixels(); ++p) {
    const double f = small.data()[p];
    foreground += f;
    if (covered.data()[p] == 0.0f) unexplained += f;
  }
  return foreground > 0 ? unexplained / foreground : 0.0;
}

// Why view v disagrees with the others ("" if it does not).
std::string Disagreement(const ViewConsensus& consensus, int v, const DensityOptions& options) {
  const double carved = consensus.carved_share[v];
  if (carved > options.view_max_carved_share &&
      carved > options.view_carved_share_ratio * consensus.median_carved_share) {
    return "its matte carves away " + Percent(carved) +
           " of what the other views agree on (the median view " +
           Percent(consensus.median_carved_share) + ")";
  }
  const double unexplained = consensus.unexplained_share[v];
  if (unexplained > options.view_max_carved_share &&
      unexplained > options.view_carved_share_ratio * consensus.median_unexplained_share) {
    return "its matte has " + Percent(unexplained) +
           " of its foreground where the other views see nothing (the median view " +
           Percent(consensus.median_unexplained_share) + ")";
  }
  return "";
}

}  // namespace

int ViewConsensus::NumDistrusted() const {
  return static_cast<int>(std::count(trusted.begin(), trusted.end(), false));
}

std::vector<std::string> ScreenForegroundMasks(const std::vector<FloatImage>& masks) {
  std::vector<double> shares;
  for (const FloatImage& mask : masks) shares.push_back(ForegroundShare(mask));
  const double median = Median(shares);
  std::vector<std::string> reasons(masks.size());
  for (size_t v = 0; v < masks.size(); ++v) {
    if (shares[v] == 0.0) {
      reasons[v] = "its matte is empty (no foreground)";
    } else if (shares[v] * kSparseForegroundRatio < median) {
      reasons[v] =
          "its matte has " + Percent(shares[v]) + " foreground, the median view " + Percent(median);
    }
  }
  return reasons;
}

ViewConsensus AssessViewConsensus(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                                  const Box3d& bounds, const DensityOptions& options,
                                  const std::vector<std::string>& screened,
                                  const ProgressTask& progress) {
  const int num_views = image_set.NumViews();
  SYLVA_CHECK(static_cast<int>(masks.size()) == num_views &&
              static_cast<int>(screened.size()) == num_views);
  ViewConsensus consensus;
  consensus.reasons = screened;
  consensus.carved_share.assign(num_views, 0.0);
  consensus.unexplained_share.assign(num_views, 0.0);
  std::vector<int> voting;
  for (int v = 0; v < num_views; ++v) {
    if (screened[v].empty()) voting.push_back(v);
  }
  consensus.allowed_dissent =
      static_cast<int>(std::floor(options.view_outlier_fraction * voting.size()));
  if (static_cast<int>(voting.size()) >= options.view_consensus_min_views &&
      consensus.allowed_dissent > 0) {
    const std::vector<SummedAreaTable> tables = MakeSummedAreaTables(masks);
    const VoxelBlock block = CoarseBlock(bounds, options.hull_resolution);
    const FootprintVotes votes =
        CountFootprintVetoes(image_set, tables, voting, block, 0.0, nullptr, progress);
    const std::vector<char> hull =
        ConsensusHull(votes, consensus.allowed_dissent, &consensus.consensus_voxels);
    // Share of the hull's voxels (that a view sees) which its mask carves
    // away, for every view: from the votes' record of who voted, or (more
    // views than it holds) in one more pass; then each view's unexplained
    // foreground, views in parallel.
    const ViewVetoCounts counts =
        votes.seen_by.empty()
            ? CountVetoesPerView(image_set, tables, voting, block, 0.0, hull, progress)
            : CountVetoesPerView(votes, voting.size(), hull);
    tbb::parallel_for(size_t{0}, voting.size(), [&](size_t k) {
      progress.CheckCancelled();
      const int v = voting[k];
      consensus.carved_share[v] =
          counts.seen[k] > 0 ? static_cast<double>(counts.vetoes[k]) / counts.seen[k] : 0.0;
      consensus.unexplained_share[v] = UnexplainedShare(image_set, masks[v], v, block, hull);
    });
    std::vector<double> carved, unexplained;
    for (int v : voting) {
      carved.push_back(consensus.carved_share[v]);
      unexplained.push_back(consensus.unexplained_share[v]);
    }
    consensus.median_carved_share = Median(carved);
    consensus.median_unexplained_share = Median(unexplained);
    for (int v : voting) consensus.reasons[v] = Disagreement(consensus, v, options);
  }
  for (const std::string& reason : consensus.reasons) consensus.trusted.push_back(reason.empty());
  return consensus;
}

}  // namespace sylva
