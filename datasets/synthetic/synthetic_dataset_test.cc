#include "datasets/synthetic/synthetic_dataset.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;

// Small, fast datasets: 128 px images.
SyntheticDatasetOptions SmallOptions(SyntheticCameraKind camera, int num_views, int num_held_out) {
  SyntheticDatasetOptions options;
  options.camera = camera;
  options.num_views = num_views;
  options.num_held_out = num_held_out;
  options.image_size = 128;
  return options;
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "sylva_synthetic_dataset_test" / name;
  fs::remove_all(dir);
  return dir;
}

// Azimuth of a view's camera centre around the target, in degrees [0, 360).
double Azimuth(const View& view, const Eigen::Vector3d& target) {
  const Eigen::Vector3d offset = view.ProjectionCenter() - target;
  const double azimuth = std::atan2(offset.y(), offset.x()) / kDegree;
  return azimuth < 0 ? azimuth + 360.0 : azimuth;
}

double Elevation(const View& view) { return std::asin(-view.ViewingDirection().z()) / kDegree; }

TEST(SyntheticDatasetTest, PinholeCamerasRingTheTree) {
  const SyntheticDatasetOptions options;  // 8 + 2 views, 512 px
  const SyntheticTree tree = GenerateSyntheticTree(options.tree, options.seed);
  const ImageSet image_set = MakeSyntheticCameras(options, tree.mesh);
  ASSERT_NO_THROW(image_set.Check("synthetic"));
  ASSERT_EQ(image_set.NumViews(), 10);
  const Camera& camera = image_set.CameraOf(0);
  EXPECT_EQ(camera.model(), CameraModel::kPinhole);
  EXPECT_NEAR(2 * std::atan(0.5 * camera.width() / camera.FocalLengthX()) / kDegree, 47.0, 1e-9);
  const Box3d box = tree.mesh.Bounds();
  double all_min_gap = 512, max_min_gap = 0;
  for (int i = 0; i < image_set.NumViews(); ++i) {
    const View& view = image_set.views[i];
    EXPECT_EQ(view.image_id, i + 1);
    EXPECT_EQ(view.name, i < 8 ? "view_0" + std::to_string(i) + ".png"
                               : "heldout_0" + std::to_string(i - 8) + ".png");
    // Looks at the box centre, at the documented elevation.
    const Eigen::Vector3d to_target = (box.center() - view.ProjectionCenter()).normalized();
    EXPECT_NEAR(to_target.dot(view.ViewingDirection()), 1.0, 1e-12);
    EXPECT_NEAR(Elevation(view), i < 8 ? 10.0 : 25.0, 1e-9);
    if (i < 8) {
      EXPECT_NEAR(std::remainder(Azimuth(view, box.center()) - 45.0 * i, 360.0), 0.0, 1e-9);
    }
    // The whole tree is in the image, with the margin (5% of 256 px) to
    // spare, and touches it (the distance is as small as that allows).
    double min_gap = 512;
    for (const Eigen::Vector3f& vertex : tree.mesh.vertices) {
      Eigen::Vector2d point_in_image;
      ASSERT_TRUE(image_set.Project(i, vertex.cast<double>(), &point_in_image));
      const double gap = std::min(point_in_image.minCoeff(), 512 - point_in_image.maxCoeff());
      min_gap = std::min(min_gap, gap);
    }
    max_min_gap = std::max(max_min_gap, min_gap);
    all_min_gap = std::min(all_min_gap, min_gap);
  }
  EXPECT_NEAR(all_min_gap, 12.8, 1e-6);
  EXPECT_LT(max_min_gap, 60);
  // Held-out views half-way between input azimuths.
  EXPECT_NEAR(Azimuth(image_set.views[8], box.center()), 22.5, 1e-9);
  EXPECT_NEAR(Azimuth(image_set.views[9], box.center()), 202.5, 1e-9);
}

TEST(SyntheticDatasetTest, TwoOrthographicViewsAreAtRightAngles) {
  const SyntheticDatasetOptions options = SmallOptions(SyntheticCameraKind::kOrthographic, 2, 1);
  const SyntheticTree tree = GenerateSyntheticTree(options.tree, options.seed);
  const ImageSet image_set = MakeSyntheticCameras(options, tree.mesh);
  ASSERT_EQ(image_set.NumViews(), 3);
  EXPECT_TRUE(image_set.CameraOf(0).IsOrthographic());
  const Eigen::Vector3d a = image_set.views[0].ViewingDirection();
  const Eigen::Vector3d b = image_set.views[1].ViewingDirection();
  EXPECT_NEAR(a.dot(b), 0.0, 1e-12);
  EXPECT_NEAR(a.z(), 0.0, 1e-12);
  EXPECT_NEAR(b.z(), 0.0, 1e-12);
  EXPECT_NEAR(Azimuth(image_set.views[2], tree.mesh.Bounds().center()), 45.0, 1e-9);
  EXPECT_NEAR(Elevation(image_set.views[2]), 25.0, 1e-9);
}

// The projected radius, in pixels, of a sphere of `radius` at `point`.
double ProjectedRadius(const ImageSet& image_set, int view_idx, const Eigen::Vector3d& point,
                       double radius) {
  const Camera& camera = image_set.CameraOf(view_idx);
  if (camera.IsOrthographic()) return camera.FocalLengthX() * radius;
  const double depth = (image_set.views[view_idx].cam_from_world * point).z();
  return camera.FocalLengthX() * radius / depth;
}

// Every trunk node that is at least a pixel wide in a view projects to a
// pixel that the matte covers; likewise points along thinner branches that
// are at least 1.5 px wide.
void ExpectSkeletonInsideMattes(const SyntheticDataset& dataset) {
  const SkeletonGraph& skeleton = dataset.tree.skeleton;
  const ImageSet& image_set = dataset.image_set;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    SCOPED_TRACE(image_set.views[v].name);
    int checked_trunk = 0, num_trunk = 0;
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      const SkeletonNode& node = skeleton.nodes[i];
      const double min_radius_px = node.order == 0 ? 0.5 : 0.75;
      if (node.order == 0) ++num_trunk;
      // The root sits on the bottom edge of side-on silhouettes: skip it.
      if (node.parent_idx < 0) continue;
      if (ProjectedRadius(image_set, v, node.position, node.radius) < min_radius_px) continue;
      Eigen::Vector2d point_in_image;
      ASSERT_TRUE(image_set.Project(v, node.position, &point_in_image));
      const int col = static_cast<int>(std::floor(point_in_image.x()));
      const int row = static_cast<int>(std::floor(point_in_image.y()));
      ASSERT_TRUE(col >= 0 && row >= 0 && col < 128 && row < 128);
      EXPECT_GT(dataset.mattes[v].at(col, row), 0.0f) << "node " << i << " order " << node.order;
      if (node.order == 0) ++checked_trunk;
    }
    EXPECT_GE(checked_trunk, 0.8 * num_trunk);
  }
}

TEST(SyntheticDatasetTest, SkeletonProjectsIntoTheMattes) {
  for (const SyntheticCameraKind kind :
       {SyntheticCameraKind::kPinhole, SyntheticCameraKind::kOrthographic}) {
    SCOPED_TRACE(SyntheticCameraKindName(kind));
    const SyntheticDataset dataset = MakeSyntheticDataset(SmallOptions(kind, 3, 1));
    ExpectSkeletonInsideMattes(dataset);
  }
  SyntheticDatasetOptions distorted = SmallOptions(SyntheticCameraKind::kPinhole, 3, 1);
  distorted.radial_distortion = -0.15;
  const SyntheticDataset dataset = MakeSyntheticDataset(distorted);
  EXPECT_EQ(dataset.image_set.CameraOf(0).model(), CameraModel::kSimpleRadial);
  ExpectSkeletonInsideMattes(dataset);
}

TEST(SyntheticDatasetTest, MattesAreThePhotosAlphaAndTheCrownIsPartlySeeThrough) {
  const SyntheticDataset dataset =
      MakeSyntheticDataset(SmallOptions(SyntheticCameraKind::kPinhole, 2, 0));
  ASSERT_EQ(dataset.photos.size(), 2u);
  ASSERT_EQ(dataset.mattes.size(), 2u);
  for (size_t v = 0; v < dataset.photos.size(); ++v) {
    const FloatImage& photo = dataset.photos[v];
    const FloatImage& matte = dataset.mattes[v];
    ASSERT_EQ(photo.channels(), 4);
    ASSERT_EQ(matte.channels(), 1);
    EXPECT_EQ(photo.Channel(3).values(), matte.values());
    int covered = 0, full = 0, partial = 0;
    for (float alpha : matte.values()) {
      covered += alpha > 0 ? 1 : 0;
      full += alpha == 1.0f ? 1 : 0;
      partial += alpha > 0 && alpha < 1 ? 1 : 0;
    }
    // The tree fills a good part of the image; many crown pixels are partial.
    EXPECT_GT(covered, 0.2 * matte.NumPixels());
    EXPECT_LT(covered, 0.8 * matte.NumPixels());
    EXPECT_GT(full, 0.3 * covered);
    EXPECT_GT(partial, 0.1 * covered);
  }
}

TEST(SyntheticDatasetTest, SameSeedSameImages) {
  SyntheticDatasetOptions options = SmallOptions(SyntheticCameraKind::kPinhole, 2, 1);
  options.image_size = 64;
  const SyntheticDataset a = MakeSyntheticDataset(options);
  const SyntheticDataset b = MakeSyntheticDataset(options);
  ASSERT_EQ(a.photos.size(), 3u);
  for (size_t v = 0; v < a.photos.size(); ++v)
    EXPECT_EQ(a.photos[v].values(), b.photos[v].values());
  EXPECT_EQ(a.held_out, std::vector<std::string>{"heldout_00.png"});
  EXPECT_TRUE(a.IsHeldOut("heldout_00.png"));
  EXPECT_FALSE(a.IsHeldOut("view_00.png"));
  options.seed = 2;
  const SyntheticDataset c = MakeSyntheticDataset(options);
  EXPECT_NE(c.mattes[0].values(), a.mattes[0].values());
}

void ExpectSameImageSet(const ImageSet& expected, const ImageSet& actual, double tolerance) {
  ASSERT_EQ(actual.NumViews(), expected.NumViews());
  ASSERT_EQ(actual.cameras.size(), 1u);
  const Camera& camera = actual.cameras.begin()->second;
  const Camera& expected_camera = expected.cameras.begin()->second;
  EXPECT_EQ(camera.model(), expected_camera.model());
  for (size_t p = 0; p < camera.params().size(); ++p) {
    EXPECT_NEAR(camera.params()[p], expected_camera.params()[p], tolerance);
  }
  for (int i = 0; i < expected.NumViews(); ++i) {
    const View& a = expected.views[i];
    const View& b = actual.views[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.image_id, b.image_id);
    EXPECT_LT((a.cam_from_world.ToMatrix() - b.cam_from_world.ToMatrix()).norm(), tolerance);
  }
}

TEST(SyntheticDatasetTest, WrittenDatasetReloads) {
  SyntheticDatasetOptions options = SmallOptions(SyntheticCameraKind::kPinhole, 3, 1);
  options.image_size = 64;
  const SyntheticDataset dataset = MakeSyntheticDataset(options);
  const fs::path dir = FreshDir("pinhole");
  WriteSyntheticDataset(dataset, options, dir);

  std::string units;
  ExpectSameImageSet(dataset.image_set, ReadCameraFile(dir / "cameras.json", &units), 1e-9);
  EXPECT_EQ(units, "m");
  ExpectSameImageSet(dataset.image_set, ReadColmapModel(dir / "colmap"), 1e-6);
  for (int v = 0; v < dataset.image_set.NumViews(); ++v) {
    const std::string& name = dataset.image_set.views[v].name;
    const FloatImage matte = ReadMatte(dir / "mattes" / name);
    ASSERT_EQ(matte.values().size(), dataset.mattes[v].values().size());
    for (size_t p = 0; p < matte.values().size(); ++p) {
      ASSERT_NEAR(matte.values()[p], dataset.mattes[v].values()[p], 0.51 / 65535);
    }
    const FloatImage photo = ReadImage(dir / "photos" / name);
    ASSERT_EQ(photo.channels(), 4);
    for (size_t p = 0; p < photo.values().size(); ++p) {
      ASSERT_NEAR(photo.values()[p], dataset.photos[v].values()[p], 0.51 / 255) << p;
    }
  }
  EXPECT_EQ(ReadFileToString(dir / "held_out.txt"), "heldout_00.png\n");
  const SkeletonGraph skeleton = ReadSkeletonJson(dir / "ground_truth" / "skeleton.json");
  EXPECT_EQ(skeleton.NumNodes(), dataset.tree.skeleton.NumNodes());
  EXPECT_EQ(skeleton.radius_source, "ground truth");
  const TriangleMesh mesh = ReadObj(dir / "ground_truth" / "tree.obj");
  EXPECT_EQ(mesh.NumVertices(), dataset.tree.mesh.NumVertices());
  EXPECT_EQ(mesh.NumTriangles(), dataset.tree.mesh.NumTriangles());
  EXPECT_NE(ReadFileToString(dir / "synth.json").find("\"seed\": 1"), std::string::npos);
  // A non-empty folder is refused.
  EXPECT_THROW(WriteSyntheticDataset(dataset, options, dir), InputError);
}

TEST(SyntheticDatasetTest, OrthographicDatasetHasNoColmapModel) {
  SyntheticDatasetOptions options = SmallOptions(SyntheticCameraKind::kOrthographic, 2, 0);
  options.image_size = 32;
  const SyntheticDataset dataset = MakeSyntheticDataset(options);
  const fs::path dir = FreshDir("orthographic");
  WriteSyntheticDataset(dataset, options, dir);
  EXPECT_FALSE(fs::exists(dir / "colmap"));
  ExpectSameImageSet(dataset.image_set, ReadCameraFile(dir / "cameras.json"), 1e-9);
  EXPECT_EQ(ReadFileToString(dir / "held_out.txt"), "");
}

TEST(SyntheticDatasetTest, OptionsAreChecked) {
  SyntheticDatasetOptions options;
  options.num_views = 0;
  EXPECT_THROW(MakeSyntheticDataset(options), InputError);
  options = SyntheticDatasetOptions();
  options.camera = SyntheticCameraKind::kOrthographic;
  options.radial_distortion = 0.1;
  EXPECT_THROW(options.Check(), InputError);
  options = SyntheticDatasetOptions();
  options.tree.cluster_radius = 0;
  EXPECT_THROW(options.Check(), InputError);
}

}  // namespace
}  // namespace sylva
