#include "reconstruct/registration/world_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "reconstruct/registration/registration_test_util.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180;

// A toy tree standing on the origin, +Z up: a trunk (cylinder of radius
// 0.15 from z = 0 to 2) under a round crown (sphere of radius 1 at z = 3), so
// 4 units tall.
constexpr double kTrunkRadius = 0.15;
constexpr double kTrunkTop = 2.0;
constexpr double kCrownRadius = 1.0;
constexpr double kCrownCentreZ = 3.0;
constexpr double kTreeHeight = 4.0;

bool HitsSphere(const Ray3d& ray) {
  const Eigen::Vector3d to_centre = Eigen::Vector3d(0, 0, kCrownCentreZ) - ray.origin;
  const double along = to_centre.dot(ray.direction);
  return along > 0 && (to_centre - along * ray.direction).norm() <= kCrownRadius;
}

bool HitsTrunk(const Ray3d& ray) {
  // |origin_xy + t direction_xy| = r: a quadratic in t.
  const Eigen::Vector2d o = ray.origin.head<2>(), d = ray.direction.head<2>();
  const double a = d.squaredNorm(), b = 2 * o.dot(d),
               c = o.squaredNorm() - kTrunkRadius * kTrunkRadius;
  const double discriminant = b * b - 4 * a * c;
  if (a == 0 || discriminant < 0) return false;
  for (const double sign : {-1.0, 1.0}) {
    const double t = (-b + sign * std::sqrt(discriminant)) / (2 * a);
    const double z = ray.origin.z() + t * ray.direction.z();
    if (t > 0 && z >= 0 && z <= kTrunkTop) return true;
  }
  return false;
}

// The toy tree's silhouette in one view (binary matte).
FloatImage RenderMatte(const ImageSet& cameras, int view_idx) {
  const Camera& camera = cameras.CameraOf(view_idx);
  FloatImage matte(camera.width(), camera.height(), 1);
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      const Ray3d ray = cameras.RayThroughPixel(view_idx, Eigen::Vector2d(x + 0.5, y + 0.5));
      matte.at(x, y) = HitsSphere(ray) || HitsTrunk(ray) ? 1.0f : 0.0f;
    }
  }
  return matte;
}

// Cameras at eye height on a circle around the tree (or an arc of it),
// looking at the trunk's top, upright (+Z up) up to a roll (degrees, the same
// for all, plus a random part) and random height errors (units).
struct Ring {
  int num_views = 12;
  double arc_degrees = 360;
  double roll_degrees = 0.0;
  double roll_jitter_degrees = 0.0;
  double height_jitter = 0.0;
  uint64_t seed = 1;
};

ImageSet RingOfCameras(const Ring& ring) {
  constexpr double kRadius = 8.0, kEyeHeight = 1.6;
  RandomEngine random(ring.seed);
  ImageSet cameras;
  cameras.cameras[1] = Camera(CameraModel::kSimplePinhole, 360, 270, {270, 180, 135});
  const int steps = ring.arc_degrees >= 360 ? ring.num_views : std::max(1, ring.num_views - 1);
  for (int i = 0; i < ring.num_views; ++i) {
    const double angle = ring.arc_degrees * kDegree * i / steps;
    const Eigen::Vector3d centre(
        kRadius * std::cos(angle), kRadius * std::sin(angle),
        kEyeHeight + random.Uniform(-ring.height_jitter, ring.height_jitter));
    View view;
    view.image_id = i + 1;
    view.name = "view" + std::to_string(i) + ".jpg";
    view.camera_id = 1;
    const Rigid3d upright =
        LookAt(centre, Eigen::Vector3d(0, 0, kTrunkTop), Eigen::Vector3d::UnitZ());
    const double roll =
        ring.roll_degrees + random.Uniform(-ring.roll_jitter_degrees, ring.roll_jitter_degrees);
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(roll * kDegree, Eigen::Vector3d::UnitZ()));
    view.cam_from_world = Rigid3d(turn * upright.rotation, turn * upright.translation);
    cameras.views.push_back(view);
  }
  return cameras;
}

ImageSet RingOfCameras(int num_views, double arc_degrees) {
  Ring ring;
  ring.num_views = num_views;
  ring.arc_degrees = arc_degrees;
  return RingOfCameras(ring);
}

std::vector<FloatImage> RenderMattes(const ImageSet& cameras) {
  std::vector<FloatImage> mattes;
  for (int i = 0; i < cameras.NumViews(); ++i) mattes.push_back(RenderMatte(cameras, i));
  return mattes;
}

// The cameras as a registration would give them: moved by `model_from_truth`.
ImageSet MoveCameras(const ImageSet& cameras, const Sim3d& model_from_truth) {
  WorldFrame frame;
  frame.world_from_model = model_from_truth;
  return TransformCameras(cameras, frame);
}

// ROMI-like: +Z down, millimetres, off-centre.
Sim3d RomiLike() {
  return Sim3d(100.0, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())),
               Eigen::Vector3d(400, 400, 398));
}

Sim3d Arbitrary() {
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -0.8, 0.5).normalized()));
  return Sim3d(0.37, rotation, Eigen::Vector3d(-2, 5, 1.5));
}

// How far the estimated frame is from the truth, all in the estimated world
// frame's units.
struct FrameErrors {
  double up_degrees = 0;    // world up vs the truth's up
  double base_offset = 0;   // the true base's distance from the origin
  double height_ratio = 0;  // estimated / true height
  double scale = 0;         // world units per truth unit
};

FrameErrors Compare(const WorldFrame& frame, const Sim3d& model_from_truth) {
  const Sim3d world_from_truth = frame.world_from_model * model_from_truth;
  FrameErrors errors;
  const Eigen::Vector3d truth_up_in_world = world_from_truth.rotation * Eigen::Vector3d::UnitZ();
  errors.up_degrees = std::acos(std::clamp(truth_up_in_world.z(), -1.0, 1.0)) / kDegree;
  errors.base_offset = (world_from_truth * Eigen::Vector3d::Zero()).norm();
  errors.scale = world_from_truth.scale;
  errors.height_ratio = frame.tree_height / (kTreeHeight * world_from_truth.scale);
  return errors;
}

// The frame estimated on `truth`'s cameras moved by `model_from_truth`, with
// the true mattes, and its errors.
struct Trial {
  WorldFrame frame;
  FrameErrors errors;
};

Trial RunTrial(const ImageSet& truth, const Sim3d& model_from_truth,
               const WorldFrameOptions& options = WorldFrameOptions()) {
  Trial trial;
  trial.frame =
      EstimateWorldFrame(MoveCameras(truth, model_from_truth), RenderMattes(truth), options);
  trial.errors = Compare(trial.frame, model_from_truth);
  return trial;
}

TEST(WorldFrameTest, FullRingRomiLikeFrame) {
  const ImageSet truth = RingOfCameras(12, 360);
  const Sim3d model_from_truth = RomiLike();
  const Trial trial = RunTrial(truth, model_from_truth);
  const WorldFrame& frame = trial.frame;
  SCOPED_TRACE(frame.BriefReport());
  EXPECT_EQ(frame.up_source, "camera ring (12 views)");
  EXPECT_EQ(frame.base_source, "mattes (12 views)");
  EXPECT_EQ(frame.units, "arbitrary");
  EXPECT_GT(frame.up_in_model.dot(Eigen::Vector3d(0, 0, -1)), std::cos(0.1 * kDegree));
  const FrameErrors& errors = trial.errors;
  EXPECT_LT(errors.up_degrees, 0.1);
  EXPECT_NEAR(errors.scale, 100.0, 1e-9);  // scale kept
  EXPECT_LT(errors.base_offset, 0.03 * kTreeHeight * errors.scale);
  EXPECT_NEAR(errors.height_ratio, 1.0, 0.03);
  // The first view looks along +Y.
  const ImageSet world = TransformCameras(MoveCameras(truth, model_from_truth), frame);
  const Eigen::Vector3d looking = world.views[0].ViewingDirection();
  EXPECT_NEAR(looking.x(), 0.0, 1e-9);
  EXPECT_GT(looking.y(), 0.9);
}

TEST(WorldFrameTest, KnownHeightSetsTheScale) {
  const ImageSet truth = RingOfCameras(12, 360);
  const Sim3d model_from_truth = Arbitrary();
  WorldFrameOptions options;
  options.known_height = 12.0;  // metres: a tree 3x the toy's model units
  const Trial trial = RunTrial(truth, model_from_truth, options);
  const WorldFrame& frame = trial.frame;
  SCOPED_TRACE(frame.BriefReport());
  EXPECT_EQ(frame.units, "m");
  EXPECT_DOUBLE_EQ(frame.tree_height, 12.0);
  const FrameErrors& errors = trial.errors;
  EXPECT_NEAR(errors.scale, 3.0, 0.03 * 3.0);
  EXPECT_LT(errors.up_degrees, 0.1);
  EXPECT_LT(errors.base_offset, 0.03 * 12.0);
}

// Hand-held photos: camera heights and roll vary a little.
TEST(WorldFrameTest, JitteredRing) {
  Ring ring;
  ring.num_views = 10;
  ring.roll_jitter_degrees = 2.0;
  ring.height_jitter = 0.2;
  ring.seed = 5;
  const ImageSet truth = RingOfCameras(ring);
  const Sim3d model_from_truth = Arbitrary();
  const Trial trial = RunTrial(truth, model_from_truth);
  const WorldFrame& frame = trial.frame;
  SCOPED_TRACE(frame.BriefReport());
  EXPECT_EQ(frame.up_source, "camera ring (10 views)");
  const FrameErrors& errors = trial.errors;
  EXPECT_LT(errors.up_degrees, 2.0);
  EXPECT_LT(errors.base_offset, 0.05 * kTreeHeight * errors.scale);
  EXPECT_NEAR(errors.height_ratio, 1.0, 0.05);
}

// An arc of a ring (6 photos over 75 degrees, as the quick benchmark's ROMI
// photos) still gives its plane, and a systematic camera roll (ROMI's is ~4
// degrees) does not bias it; the level-axes estimate would lean by ~4.
TEST(WorldFrameTest, ArcOfARingWithRolledCameras) {
  Ring ring;
  ring.num_views = 6;
  ring.arc_degrees = 75;
  ring.roll_degrees = 4.0;
  const ImageSet truth = RingOfCameras(ring);
  const Sim3d model_from_truth = Arbitrary();
  const Trial trial = RunTrial(truth, model_from_truth);
  const WorldFrame& frame = trial.frame;
  SCOPED_TRACE(frame.BriefReport());
  EXPECT_EQ(frame.up_source, "camera ring (6 views)");
  const FrameErrors& errors = trial.errors;
  EXPECT_LT(errors.up_degrees, 0.1);
  EXPECT_LT(errors.base_offset, 0.05 * kTreeHeight * errors.scale);

  WorldFrameOptions no_ring;
  no_ring.ring_min_views = 100;
  const Trial level = RunTrial(truth, model_from_truth, no_ring);
  EXPECT_EQ(level.frame.up_source, "level camera x axes (6 views)");
  EXPECT_GT(level.errors.up_degrees, 2.0);
}

// Three photos over 60 degrees are no ring: up comes from the level x axes,
// exactly for upright photos even though they look up at the tree.
TEST(WorldFrameTest, FewPhotosUseLevelCameraAxes) {
  const ImageSet truth = RingOfCameras(3, 60);
  const Sim3d model_from_truth = Arbitrary();
  const Trial trial = RunTrial(truth, model_from_truth);
  const WorldFrame& frame = trial.frame;
  SCOPED_TRACE(frame.BriefReport());
  EXPECT_EQ(frame.up_source, "level camera x axes (3 views)");
  const FrameErrors& errors = trial.errors;
  EXPECT_LT(errors.up_degrees, 1e-6);
  EXPECT_LT(errors.base_offset, 0.05 * kTreeHeight * errors.scale);
  EXPECT_NEAR(errors.height_ratio, 1.0, 0.05);
}

TEST(WorldFrameTest, OneViewUsesItsImageUp) {
  const ImageSet truth = RingOfCameras(1, 0);
  WorldFrameOptions options;
  options.base = "keep";
  const WorldFrame frame = EstimateWorldFrame(truth, {}, options);
  EXPECT_EQ(frame.up_source, "camera image up (1 view)");
  // The camera looks up at the trunk's top: its image up leans by the pitch.
  const double pitch = std::atan2(0.4, 8.0) / kDegree;
  EXPECT_NEAR(std::acos(frame.up_in_model.z()) / kDegree, pitch, 1e-6);
  EXPECT_EQ(frame.base_source, "kept (origin)");
}

// A speck of foreground below the tree in one matte is ignored.
TEST(WorldFrameTest, SpecksBelowTheTreeAreIgnored) {
  const ImageSet truth = RingOfCameras(8, 360);
  std::vector<FloatImage> mattes = RenderMattes(truth);
  const WorldFrame clean = EstimateWorldFrame(truth, mattes, WorldFrameOptions());
  for (int y = 260; y < 263; ++y) {
    for (int x = 20; x < 23; ++x) mattes[3].at(x, y) = 1.0f;
  }
  const WorldFrame specked = EstimateWorldFrame(truth, mattes, WorldFrameOptions());
  EXPECT_LT((specked.base_in_model - clean.base_in_model).norm(), 1e-9);
  EXPECT_LT(clean.base_in_model.norm(), 0.03 * kTreeHeight);
}

TEST(WorldFrameTest, ExplicitAxesAndKeep) {
  const ImageSet truth = RingOfCameras(6, 360);
  const Sim3d model_from_truth = RomiLike();
  const ImageSet model = MoveCameras(truth, model_from_truth);
  WorldFrameOptions options;
  options.up = "-z";
  const WorldFrame frame = EstimateWorldFrame(model, RenderMattes(truth), options);
  EXPECT_EQ(frame.up_source, "option -z");
  // Half a turn about x: x kept, y and z flipped.
  EXPECT_LT((frame.world_from_model.rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX())
                .norm(),
            1e-12);
  EXPECT_LT((frame.world_from_model.rotation * Eigen::Vector3d::UnitZ() + Eigen::Vector3d::UnitZ())
                .norm(),
            1e-12);
  EXPECT_LT(Compare(frame, model_from_truth).base_offset, 0.03 * kTreeHeight * 100);

  // Each axis option turns that axis to +Z.
  for (const std::string axis : {"+x", "-x", "+y", "-y", "+z", "-z"}) {
    options.up = axis;
    options.base = "keep";
    const WorldFrame turned = EstimateWorldFrame(model, {}, options);
    EXPECT_LT(
        (turned.world_from_model.rotation * turned.up_in_model - Eigen::Vector3d::UnitZ()).norm(),
        1e-12)
        << axis;
    EXPECT_EQ(turned.world_from_model.translation, Eigen::Vector3d::Zero());
  }
  options.up = "keep";
  const WorldFrame kept = EstimateWorldFrame(model, {}, options);
  EXPECT_TRUE(kept.world_from_model.rotation.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_EQ(kept.world_from_model.scale, 1.0);
}

TEST(WorldFrameTest, WithoutMattesTheBaseIsWhereTheCamerasLook) {
  const ImageSet truth = RingOfCameras(8, 360);
  const WorldFrame frame = EstimateWorldFrame(truth, {}, WorldFrameOptions());
  EXPECT_NE(frame.base_source.find("optical axes"), std::string::npos) << frame.base_source;
  EXPECT_LT((frame.base_in_model - Eigen::Vector3d(0, 0, kTrunkTop)).norm(), 1e-6);
  EXPECT_EQ(frame.tree_height, 0.0);
}

TEST(WorldFrameTest, BadInputIsAnInputError) {
  const ImageSet truth = RingOfCameras(4, 360);
  std::vector<FloatImage> mattes = RenderMattes(truth);
  const auto expect_error = [&](const std::vector<FloatImage>& these,
                                const WorldFrameOptions& options, const std::string& source_start) {
    try {
      EstimateWorldFrame(truth, these, options);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source().rfind(source_start, 0), 0u) << error.what();
    }
  };
  expect_error({mattes[0]}, WorldFrameOptions(), "mattes");
  std::vector<FloatImage> wrong = mattes;
  wrong[2] = FloatImage(100, 100, 1);
  expect_error(wrong, WorldFrameOptions(), "mattes (view 'view2.jpg')");
  wrong[2] = FloatImage(360, 270, 3);
  expect_error(wrong, WorldFrameOptions(), "mattes (view 'view2.jpg')");
  WorldFrameOptions known;
  known.known_height = 10;
  expect_error({}, known, "WorldFrame.known_height");
  WorldFrameOptions bad;
  bad.up = "up";
  expect_error(mattes, bad, "WorldFrame.up");
  bad = WorldFrameOptions();
  bad.consensus = 0;
  expect_error(mattes, bad, "WorldFrame.consensus");
  bad = WorldFrameOptions();
  bad.base = "ground";
  expect_error(mattes, bad, "WorldFrame.base");
}

// Mattes at a lower resolution than the photos work the same.
TEST(WorldFrameTest, DownsampledMattes) {
  const ImageSet truth = RingOfCameras(8, 360);
  std::vector<FloatImage> small;
  for (const FloatImage& matte : RenderMattes(truth)) small.push_back(DownsampleBox(matte, 2));
  const WorldFrame frame = EstimateWorldFrame(truth, small, WorldFrameOptions());
  EXPECT_LT(frame.base_in_model.norm(), 0.04 * kTreeHeight);
  EXPECT_NEAR(frame.tree_height / kTreeHeight, 1.0, 0.05);
}

TEST(WorldFrameTest, TransformCamerasKeepsProjections) {
  ImageSet model = RingOfCameras(4, 360);
  model.cameras[2] = Camera::Orthographic(360, 270, 30.0);
  model.views[1].camera_id = 2;
  Point3D point;
  point.point3d_id = 1;
  point.position = Eigen::Vector3d(0.3, -0.2, 1.1);
  model.points.push_back(point);
  WorldFrame frame;
  frame.world_from_model = Arbitrary();
  const ImageSet world = TransformCameras(model, frame);
  const Eigen::Vector3d point_in_model(0.5, 0.4, 2.5);
  for (int i = 0; i < model.NumViews(); ++i) {
    Eigen::Vector2d before, after;
    ASSERT_TRUE(model.Project(i, point_in_model, &before));
    ASSERT_TRUE(world.Project(i, frame.world_from_model * point_in_model, &after));
    EXPECT_LT((before - after).norm(), 1e-9) << "view " << i;
  }
  EXPECT_LT((world.points[0].position - frame.world_from_model * model.points[0].position).norm(),
            1e-12);
}

// ROMI's own cameras (+Z down, mm) with its simple mattes: the plant stands
// up, and its base lands at the bottom of the pot (a white foam cube, ~45 mm
// tall, its top, where the stem enters, near z = 400 mm; the cube's bottom is
// cut off by the bottom edge of most photos, only a few see it). The pot is
// not on the turntable's axis: it moves across the photos by ~30 mm.
TEST(WorldFrameTest, RomiRealPlantStandsUp) {
  const std::filesystem::path dataset =
      std::filesystem::path(SYLVA_SOURCE_DIR) / "datasets" / "romi-real-plant-24";
  const ImageSet cameras = ReadColmapModelText(dataset / "colmap");
  std::vector<FloatImage> mattes;
  for (const View& view : cameras.views) {
    mattes.push_back(DownsampleBox(RomiMatte(ReadImage(dataset / "images" / view.name)), 4));
  }
  const WorldFrame frame = EstimateWorldFrame(cameras, mattes, WorldFrameOptions());
  std::cout << "ROMI: " << frame.BriefReport() << "; up " << frame.up_in_model.transpose()
            << "; base " << frame.base_in_model.transpose() << " mm\n";
  EXPECT_EQ(frame.up_source, "camera ring (24 views)");
  EXPECT_EQ(frame.base_source, "mattes (24 views)");
  EXPECT_GT(frame.up_in_model.dot(Eigen::Vector3d(0, 0, -1)), std::cos(0.5 * kDegree));
  // The ring's centre (PROVENANCE.md: 399.5, 399.5 mm).
  EXPECT_LT((frame.base_in_model.head<2>() - Eigen::Vector2d(399.5, 399.5)).norm(), 40.0);
  EXPECT_GT(frame.base_in_model.z(), 395.0);
  EXPECT_LT(frame.base_in_model.z(), 455.0);
  // The plant's top is near z = -22 mm (PROVENANCE.md).
  EXPECT_NEAR(frame.tree_height, frame.base_in_model.z() + 22.0, 15.0);
  // Upright in the new frame: the top above the base.
  const ImageSet world = TransformCameras(cameras, frame);
  EXPECT_NEAR((frame.world_from_model * Eigen::Vector3d(400, 420, -22)).z(), frame.tree_height,
              15.0);
  for (const View& view : world.views) EXPECT_GT(view.ProjectionCenter().z(), 400.0);
}

}  // namespace
}  // namespace sylva
