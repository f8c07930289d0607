// The density stage's shortcuts give what the direct computations give:
// footprint columns found all-zero with one look-up (view_sampling.cc), the
// per-view veto counts of one pass, and the pixels the ray system skips
// because no unknown is in their reach (ray_system.cc).
#include "reconstruct/density/view_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "reconstruct/density/ray_system.h"

namespace sylva {
namespace {

// Pinhole views around a block, close enough that a voxel spans pixels.
ImageSet RingViews(int num_views, int size) {
  ImageSet set;
  set.cameras[1] = Camera::Pinhole(size, size, 1.2 * size);
  for (int v = 0; v < num_views; ++v) {
    const double azimuth = 2 * M_PI * v / num_views + 0.3;
    const double elevation = 0.15 + 0.25 * (v % 3);
    const Eigen::Vector3d center(4 * std::cos(azimuth) * std::cos(elevation),
                                 4 * std::sin(azimuth) * std::cos(elevation),
                                 1.0 + 4 * std::sin(elevation));
    View view;
    view.image_id = v + 1;
    view.name = "v" + std::to_string(v) + ".png";
    view.camera_id = 1;
    view.cam_from_world = LookAt(center, Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d::UnitZ());
    set.views.push_back(view);
  }
  return set;
}

// Wide-angle cameras with strong lens distortion (barrel, tangential), on a
// ring close enough that the block fills their images, out to the corners
// where the distortion is strongest.
ImageSet DistortedRingViews(int num_views, int size) {
  ImageSet set = RingViews(num_views, size);
  const double f = 0.55 * size, c = size / 2.0;
  set.cameras[1] = Camera(CameraModel::kOpenCV, size, size, {f, f, c, c, -0.3, 0.08, 0.01, -0.01});
  for (View& view : set.views) {
    const Eigen::Vector3d center = view.cam_from_world.Inverse().translation;
    const Eigen::Vector3d target(0, 0, 1.0);
    view.cam_from_world =
        LookAt(target + 0.6 * (center - target), target, Eigen::Vector3d::UnitZ());
  }
  return set;
}

VoxelBlock Block(int n) {
  VoxelBlock block;
  block.voxel_size = 2.0 / n;
  block.lower_corner = Eigen::Vector3d(-1.0, -1.0, 0.0);
  block.dims = Eigen::Vector3i::Constant(n);
  return block;
}

// Mattes with large empty regions (where the shortcut applies), soft values
// and isolated specks (which it must not miss): a disc with a soft rim, a
// stripe, and single faint pixels scattered over the background.
std::vector<FloatImage> Mattes(int num_views, int size, int speck_period = 97) {
  std::vector<FloatImage> mattes;
  for (int v = 0; v < num_views; ++v) {
    FloatImage matte(size, size, 1, 0.0f);
    const double cx = size * (0.45 + 0.02 * v), cy = size * 0.5, r = size * 0.22;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
        if (d < r) matte.at(x, y) = static_cast<float>(std::min(1.0, (r - d) / 4.0));
        if (std::abs(x - size / 3) < 2 && y > size / 2) matte.at(x, y) = 0.8f;
        if ((x * 7 + y * 13 + v) % speck_period == 0) matte.at(x, y) = 1e-6f;
      }
    }
    mattes.push_back(matte);
  }
  return mattes;
}

// A voxel's footprint mean in view v computed directly: the bounding
// rectangle of its 8 projected corners, -1 if a corner is behind the camera.
double DirectFootprintMean(const ImageSet& set, int v, const SummedAreaTable& table,
                           const VoxelBlock& block, int64_t i) {
  const ViewProjector projector(set, v);
  const Eigen::Vector3i ijk = block.VoxelFromLinear(i);
  float x0 = std::numeric_limits<float>::max(), y0 = x0;
  float x1 = std::numeric_limits<float>::lowest(), y1 = x1;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3i c = ijk + Eigen::Vector3i(corner & 1, (corner >> 1) & 1, corner >> 2);
    Eigen::Vector2d pixel;
    if (!projector.Project(block.lower_corner + block.voxel_size * c.cast<double>(), &pixel)) {
      return -1.0;
    }
    const Eigen::Vector2f p = pixel.cast<float>();
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  return table.BoxMean(x0, y0, x1, y1);
}

// How many voxels' means were 0 and how many positive.
struct MeanKinds {
  int64_t zero = 0, positive = 0;
};

// Each voxel's fast mean is the direct one, exactly (both through BoxMean,
// which gives exactly 0 over zero pixels).
void ExpectDirectMeans(const std::vector<float>& fast, const std::function<double(int64_t)>& direct,
                       const std::string& what, MeanKinds* kinds) {
  for (size_t i = 0; i < fast.size(); ++i) {
    ASSERT_EQ(fast[i], static_cast<float>(direct(static_cast<int64_t>(i))))
        << what << " voxel " << i;
    ++(fast[i] == 0.0f ? kinds->zero : kinds->positive);
  }
}

TEST(ViewSamplingTest, FootprintMeansMatchDirectMeans) {
  const int views = 5, size = 96;
  const ImageSet set = RingViews(views, size);
  const std::vector<SummedAreaTable> tables = MakeSummedAreaTables(Mattes(views, size));
  const VoxelBlock block = Block(20);
  // One view at a time (a minimum over views would hide one view's error).
  MeanKinds kinds;
  for (int v = 0; v < views; ++v) {
    const std::vector<int> one = {v};
    const std::vector<float> fast =
        MinFootprintMeans(set, tables, block, ProgressTask(nullptr, "test"), &one);
    ExpectDirectMeans(
        fast,
        [&](int64_t i) { return std::max(0.0, DirectFootprintMean(set, v, tables[v], block, i)); },
        "view " + std::to_string(v), &kinds);
  }
  // Both kinds are present, so both paths were taken.
  EXPECT_GT(kinds.zero, views * block.NumVoxels() / 10);
  EXPECT_GT(kinds.positive, views * block.NumVoxels() / 20);
}

// The (rank + 1)-th smallest direct footprint mean over the views that see
// a voxel (where fewer see it, the largest of theirs; 0 where none does).
double DirectLowMean(const ImageSet& set, const std::vector<SummedAreaTable>& tables,
                     const VoxelBlock& block, int rank, int64_t i) {
  std::vector<double> means;
  for (int v = 0; v < set.NumViews(); ++v) {
    const double mean = DirectFootprintMean(set, v, tables[v], block, i);
    if (mean >= 0.0) means.push_back(static_cast<float>(mean));
  }
  if (means.empty()) return 0.0;
  std::sort(means.begin(), means.end());
  return means[std::min<size_t>(rank, means.size() - 1)];
}

// Over all views at once, bricks that enough views see empty are settled
// without looking at the other views: the result is still the direct one,
// at ranks 0-2, with pinhole cameras (bricks tested from their 8 corners),
// distorted ones (the corners' rectangle widened by the edges' bend: a
// slight distortion, and a close wide-angle camera with strong barrel and
// tangential distortion that bends bricks' edges by up to 0.57 px) and an
// orthographic one. (Removing the widening does not fail it: the bent
// slivers hold no non-zero pixel here.)
TEST(ViewSamplingTest, LowFootprintMeansOverAllViewsMatchDirectMeans) {
  const int views = 7, size = 96;
  ImageSet set = RingViews(views, size);
  set.cameras[2] = Camera(CameraModel::kSimpleRadial, size, size, {1.2 * size, 48, 48, -0.08});
  set.cameras[3] = Camera::Orthographic(size, size, size / 3.0);
  set.cameras[4] = DistortedRingViews(1, size).cameras.at(1);
  set.views[1].camera_id = 2;
  set.views[4].camera_id = 3;
  set.views[6].camera_id = 4;
  set.views[6].cam_from_world = DistortedRingViews(views, size).views[6].cam_from_world;
  // Specks rare enough for whole bricks to be empty in some views.
  const std::vector<SummedAreaTable> tables = MakeSummedAreaTables(Mattes(views, size, 1999));
  const VoxelBlock block = Block(24);
  for (int rank = 0; rank <= 2; ++rank) {
    const std::vector<float> fast =
        LowFootprintMeans(set, tables, block, rank, ProgressTask(nullptr, "test"));
    MeanKinds kinds;
    ExpectDirectMeans(
        fast, [&](int64_t i) { return DirectLowMean(set, tables, block, rank, i); },
        "rank " + std::to_string(rank), &kinds);
    EXPECT_GT(kinds.zero, block.NumVoxels() / 4) << "rank " << rank;
    EXPECT_GT(kinds.positive, block.NumVoxels() / 50) << "rank " << rank;
  }
}

TEST(ViewSamplingTest, PerViewVetoesMatchOneViewAtATime) {
  const int views = 4, size = 80;
  const ImageSet set = RingViews(views, size);
  const std::vector<SummedAreaTable> tables = MakeSummedAreaTables(Mattes(views, size));
  const VoxelBlock block = Block(16);
  std::vector<char> wanted(block.NumVoxels(), 0);
  for (int64_t i = 0; i < block.NumVoxels(); i += 3) wanted[i] = 1;
  const std::vector<int> all = {0, 1, 2, 3};
  const ViewVetoCounts counts =
      CountVetoesPerView(set, tables, all, block, 0.0, wanted, ProgressTask(nullptr, "test"));
  // The same counts from the votes' record of which view voted.
  const FootprintVotes votes =
      CountFootprintVetoes(set, tables, all, block, 0.0, nullptr, ProgressTask(nullptr, "test"));
  const ViewVetoCounts recorded = CountVetoesPerView(votes, all.size(), wanted);
  EXPECT_EQ(recorded.seen, counts.seen);
  EXPECT_EQ(recorded.vetoes, counts.vetoes);
  for (int v = 0; v < views; ++v) {
    const FootprintVotes votes =
        CountFootprintVetoes(set, tables, {v}, block, 0.0, &wanted, ProgressTask(nullptr, "test"));
    int64_t seen = 0, vetoes = 0;
    for (int64_t i = 0; i < block.NumVoxels(); ++i) {
      seen += votes.seen[i];
      vetoes += votes.vetoes[i];
    }
    EXPECT_EQ(counts.seen[v], seen) << "view " << v;
    EXPECT_EQ(counts.vetoes[v], vetoes) << "view " << v;
    EXPECT_GT(vetoes, 0);
    EXPECT_LT(vetoes, seen);
  }
}

class RaySystemTest : public testing::TestWithParam<bool> {};

TEST_P(RaySystemTest, SkipsOnlyPixelsThatReachNoUnknown) {
  // Pinhole cameras, and (the parameter) cameras with lens distortion,
  // whose reachable pixels are found in the normalized plane.
  const int views = 3, size = 64;
  const ImageSet set = GetParam() ? DistortedRingViews(views, size) : RingViews(views, size);
  const std::vector<FloatImage> mattes = Mattes(views, size);
  const VoxelBlock block = Block(24);
  // Unknowns: a small ball off-centre, so most pixels reach none, and a
  // box filling whole cells of the skipping's grid, whose outline the
  // rays graze.
  std::vector<int32_t> column_of_voxel(block.NumVoxels(), -1);
  int32_t columns = 0;
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    const Eigen::Vector3i ijk = block.VoxelFromLinear(i);
    const Eigen::Vector3d p = block.VoxelCenter(ijk);
    const bool in_box = (ijk.array() >= 4).all() && (ijk.array() < 12).all();
    if ((p - Eigen::Vector3d(0.3, -0.2, 1.2)).norm() < 0.35 || in_box) {
      column_of_voxel[i] = columns++;
    }
  }
  std::vector<ViewSampling> sampling;
  for (int v = 0; v < views; ++v) sampling.push_back(ViewSampling{2, 6, size, size});
  std::vector<FloatImage> small;
  for (const FloatImage& matte : mattes) small.push_back(DownsampleBox(matte, 2));
  const RaySystem system = BuildRaySystem(set, sampling, small, block, column_of_voxel, columns,
                                          0.99, 0.5, 0.01, ProgressTask(nullptr, "test"));
  // Every pixel traced: the rows that are not empty, in order.
  int64_t row = 0, skipped = 0;
  std::vector<std::pair<int32_t, float>> entries;
  for (int v = 0; v < views; ++v) {
    for (int y = 0; y < sampling[v].height(); ++y) {
      for (int x = 0; x < sampling[v].width(); ++x) {
        PixelRow(set, v, sampling[v], x, y, block, column_of_voxel, &entries);
        if (entries.empty()) {
          ++skipped;
          continue;
        }
        ASSERT_LT(row, system.matrix.NumRows());
        const int64_t begin = system.matrix.row_offsets[row];
        ASSERT_EQ(system.matrix.row_offsets[row + 1] - begin, static_cast<int64_t>(entries.size()))
            << "view " << v << " pixel " << x << "," << y;
        const double weight = std::max(1.0 - small[v].at(x, y), 0.01);
        for (size_t k = 0; k < entries.size(); ++k) {
          EXPECT_EQ(system.matrix.cols[begin + k], entries[k].first);
          EXPECT_EQ(system.matrix.values[begin + k],
                    static_cast<float>(entries[k].second * weight));
        }
        ++row;
      }
    }
  }
  EXPECT_EQ(row, system.matrix.NumRows());
  EXPECT_GT(row, 50);
  EXPECT_GT(skipped, row);  // most pixels reach no unknown
}

INSTANTIATE_TEST_SUITE_P(Cameras, RaySystemTest, testing::Bool(),
                         [](const testing::TestParamInfo<bool>& info) {
                           return info.param ? "Distorted" : "Pinhole";
                         });

}  // namespace
}  // namespace sylva
