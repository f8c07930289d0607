#include "reconstruct/registration/loose_registration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int kSize = 400;  // test images are kSize x kSize

double RotationErrorDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b) / kDegree;
}

// A camera looking at (0, 0, target_height) from azimuth / elevation.
View TrueView(int id, const std::string& name, double azimuth_deg, double elevation_deg,
              double distance, double target_height) {
  const Eigen::Vector3d target(0, 0, target_height);
  const Eigen::Vector3d direction(
      std::cos(elevation_deg * kDegree) * std::cos(azimuth_deg * kDegree),
      std::cos(elevation_deg * kDegree) * std::sin(azimuth_deg * kDegree),
      std::sin(elevation_deg * kDegree));
  View view;
  view.image_id = view.camera_id = id;
  view.name = name;
  view.cam_from_world = LookAt(target + distance * direction, target, Eigen::Vector3d::UnitZ());
  return view;
}

Eigen::Vector2d ProjectOrDie(const ImageSet& set, int view_idx, const Eigen::Vector3d& point) {
  Eigen::Vector2d pixel;
  SYLVA_CHECK(set.Project(view_idx, point, &pixel));
  return pixel;
}

// Adds a point clicked (with Gaussian noise of `sigma` px) in every view of
// `truth` to `setup`.
void Click(const ImageSet& truth, const std::string& name, const Eigen::Vector3d& point,
           double sigma, RandomEngine* random, LooseSetup* setup) {
  LoosePoint loose_point;
  loose_point.name = name;
  for (int v = 0; v < truth.NumViews(); ++v) {
    const Eigen::Vector2d noise(random->Normal(0, sigma), random->Normal(0, sigma));
    loose_point.observations.push_back({v, ProjectOrDie(truth, v, point) + noise});
  }
  setup->points.push_back(loose_point);
}

LooseSetup SetupFor(const ImageSet& truth, LooseProjection projection) {
  LooseSetup setup;
  setup.source = "test.json";
  for (const View& view : truth.views) {
    LoosePhoto photo;
    photo.name = view.name;
    const Eigen::Vector3d angles = LooseAnglesDeg(view.cam_from_world.rotation);
    photo.azimuth_deg = angles.x();
    photo.elevation_deg = angles.y();
    photo.roll_deg = angles.z();
    photo.projection = projection;
    if (projection == LooseProjection::kPerspective) {
      photo.focal_length_px = truth.CameraOf(view).FocalLengthX();
    }
    setup.photos.push_back(photo);
  }
  return setup;
}

std::map<std::string, Eigen::Vector2i> Sizes(const LooseSetup& setup) {
  std::map<std::string, Eigen::Vector2i> sizes;
  for (const LoosePhoto& photo : setup.photos) sizes[photo.name] = Eigen::Vector2i(kSize, kSize);
  return sizes;
}

ImageSet PerspectiveTruth(const std::vector<double>& azimuths, double elevation) {
  ImageSet truth;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const int id = static_cast<int>(i) + 1;
    truth.cameras[id] = Camera::Pinhole(kSize, kSize, 1.1 * kSize);
    truth.views.push_back(
        TrueView(id, "p" + std::to_string(i) + ".jpg", azimuths[i], elevation, 14.0, 2.5));
  }
  return truth;
}

ImageSet OrthographicTruth(const std::vector<double>& azimuths) {
  ImageSet truth;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const int id = static_cast<int>(i) + 1;
    truth.cameras[id] = Camera::Orthographic(kSize, kSize, kSize / 7.0);
    truth.views.push_back(TrueView(id, "o" + std::to_string(i) + ".png", azimuths[i], 0, 20, 2.5));
  }
  return truth;
}

// ---- Angles ------------------------------------------------------------------

TEST(LooseAnglesTest, ZeroRollIsLookAtWithZUp) {
  for (double azimuth : {0.0, 37.0, 90.0, -150.0}) {
    for (double elevation : {-20.0, 0.0, 35.0}) {
      const View view = TrueView(1, "v", azimuth, elevation, 10, 0);
      EXPECT_LT(
          RotationErrorDeg(LooseCamFromWorld(azimuth, elevation, 0), view.cam_from_world.rotation),
          1e-9);
    }
  }
}

TEST(LooseAnglesTest, AnglesRoundTrip) {
  RandomEngine random(7);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d angles(random.Uniform(-179, 179), random.Uniform(-80, 80),
                                 random.Uniform(-179, 179));
    const Eigen::Vector3d back =
        LooseAnglesDeg(LooseCamFromWorld(angles.x(), angles.y(), angles.z()));
    EXPECT_LT((back - angles).norm(), 1e-8) << angles.transpose() << " -> " << back.transpose();
  }
}

TEST(LooseAnglesTest, PositiveRollTurnsThePictureCounterClockwise) {
  ImageSet set;
  set.cameras[1] = Camera::Orthographic(kSize, kSize, 10);
  View view;
  view.camera_id = 1;
  view.name = "v";
  view.cam_from_world = Rigid3d(LooseCamFromWorld(0, 0, 10), Eigen::Vector3d(0, 0, 5));
  set.views.push_back(view);
  // The world's up direction in the picture: upwards and to the left.
  const Eigen::Vector2d up = ProjectOrDie(set, 0, Eigen::Vector3d::UnitZ()) -
                             ProjectOrDie(set, 0, Eigen::Vector3d::Zero());
  EXPECT_LT(up.y(), 0);
  EXPECT_LT(up.x(), 0);
  EXPECT_NEAR(std::atan2(-up.x(), -up.y()) / kDegree, 10.0, 1e-9);
}

// ---- Initial cameras -------------------------------------------------------

TEST(InitialLooseCamerasTest, ClickedBaseAndTopGiveTheTrueCameras) {
  const double height = 5.0;
  for (LooseProjection projection :
       {LooseProjection::kPerspective, LooseProjection::kOrthographic}) {
    const ImageSet truth = projection == LooseProjection::kPerspective
                               ? PerspectiveTruth({30, 150}, 12)
                               : OrthographicTruth({0, 90});
    LooseSetup setup = SetupFor(truth, projection);
    setup.tree_height = height;
    RandomEngine random(1);
    Click(truth, "base", Eigen::Vector3d::Zero(), 0.0, &random, &setup);
    Click(truth, "top", Eigen::Vector3d(0, 0, height), 0.0, &random, &setup);
    LooseInitSummary summary;
    const ImageSet initial = InitialLooseCameras(setup, Sizes(setup), {}, {}, &summary);
    ASSERT_EQ(initial.NumViews(), 2);
    for (int v = 0; v < 2; ++v) {
      EXPECT_EQ(summary.views[v].base_source, LooseAnchorSource::kClicked);
      EXPECT_EQ(summary.views[v].top_source, LooseAnchorSource::kClicked);
      EXPECT_NEAR(initial.CameraOf(v).FocalLengthX(), truth.CameraOf(v).FocalLengthX(), 1e-6);
      // Same image of every point (the projection centre of an orthographic
      // camera is arbitrary).
      for (const Eigen::Vector3d& p : {Eigen::Vector3d(1, -2, 3), Eigen::Vector3d(-1.5, 0.5, 1)}) {
        EXPECT_LT((ProjectOrDie(initial, v, p) - ProjectOrDie(truth, v, p)).norm(), 1e-6);
      }
    }
    EXPECT_TRUE(summary.warnings.empty()) << summary.BriefReport();
  }
}

TEST(InitialLooseCamerasTest, FocalLengthFromTheDistanceOrTheDefault) {
  const double height = 5.0, elevation = 12.0;
  const ImageSet truth = PerspectiveTruth({30, 150}, elevation);
  LooseSetup setup = SetupFor(truth, LooseProjection::kPerspective);
  setup.tree_height = height;
  setup.photos[0].focal_length_px = 0;
  setup.photos[0].distance = 14.0 * std::cos(elevation * kDegree);  // to the trunk, horizontally
  setup.photos[1].focal_length_px = 0;
  RandomEngine random(1);
  Click(truth, "base", Eigen::Vector3d::Zero(), 0.0, &random, &setup);
  Click(truth, "top", Eigen::Vector3d(0, 0, height), 0.0, &random, &setup);
  LooseInitOptions options;
  const ImageSet initial = InitialLooseCameras(setup, Sizes(setup), {}, options);
  // The distance rule is a far-away approximation: within 10 % here.
  EXPECT_NEAR(initial.CameraOf(0).FocalLengthX() / truth.CameraOf(0).FocalLengthX(), 1.0, 0.1);
  EXPECT_DOUBLE_EQ(initial.CameraOf(1).FocalLengthX(), options.default_focal_factor * kSize);
  // Either way base and top land where they were clicked.
  for (int v = 0; v < 2; ++v) {
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, height)}) {
      EXPECT_LT((ProjectOrDie(initial, v, p) - ProjectOrDie(truth, v, p)).norm(), 1e-6);
    }
  }
}

// A matte of a rotationally symmetric tree (trunk of radius 0.15 up to 2,
// crown a sphere of radius 1.5 centred at 3.5, so 5 tall) seen by an
// orthographic view at elevation 0.
FloatImage SymmetricTreeMatte(const ImageSet& set, int view_idx) {
  FloatImage matte(kSize, kSize, 1);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const Ray3d ray = set.RayThroughPixel(view_idx, Eigen::Vector2d(x + 0.5, y + 0.5));
      // The ray's point in the vertical plane through the axis.
      const Eigen::Vector3d p = ray.origin - ray.direction * ray.direction.dot(ray.origin);
      const double across = p.head<2>().norm();
      const bool trunk = p.z() >= 0 && p.z() <= 2.0 && across <= 0.15;
      const bool crown = (p - Eigen::Vector3d(0, 0, 3.5)).norm() <= 1.5;
      matte.at(x, y) = trunk || crown ? 1.0f : 0.0f;
    }
  }
  return matte;
}

TEST(InitialLooseCamerasTest, MattesGiveBaseAndScale) {
  ImageSet truth = OrthographicTruth({0, 90});
  // Off-centre: the tree's base is not at the image centre.
  truth.views[1].cam_from_world.translation += Eigen::Vector3d(0.8, -0.4, 0);
  LooseSetup setup = SetupFor(truth, LooseProjection::kOrthographic);
  setup.tree_height = 5.0;
  std::map<std::string, FloatImage> mattes;
  for (int v = 0; v < 2; ++v) mattes[truth.views[v].name] = SymmetricTreeMatte(truth, v);
  LooseInitSummary summary;
  const ImageSet initial = InitialLooseCameras(setup, Sizes(setup), mattes, {}, &summary);
  const double pixels_per_unit = kSize / 7.0;
  for (int v = 0; v < 2; ++v) {
    EXPECT_EQ(summary.views[v].base_source, LooseAnchorSource::kMatte);
    // One pixel of the ~286-pixel tall tree.
    EXPECT_NEAR(initial.CameraOf(v).FocalLengthX() / pixels_per_unit, 1.0, 0.01);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 5)}) {
      EXPECT_LT((ProjectOrDie(initial, v, p) - ProjectOrDie(truth, v, p)).norm(), 1.5) << v;
    }
  }
}

TEST(InitialLooseCamerasTest, WithoutClicksOrMattesTheTreeFillsThePhoto) {
  LooseSetup setup = SetupFor(OrthographicTruth({0, 90}), LooseProjection::kOrthographic);
  LooseInitOptions options;
  LooseInitSummary summary;
  const ImageSet initial = InitialLooseCameras(setup, Sizes(setup), {}, options, &summary);
  EXPECT_EQ(summary.warnings.size(), 4u);  // base and top of both photos
  EXPECT_FALSE(summary.height_known);
  EXPECT_EQ(summary.units, "arbitrary");
  // The assumed height spans the middle 80 % of the photo.
  EXPECT_NEAR(initial.CameraOf(0).FocalLengthX() * options.assumed_tree_height,
              options.fallback_fill * kSize, 1e-9);
  EXPECT_LT((ProjectOrDie(initial, 1, Eigen::Vector3d::Zero()) -
             Eigen::Vector2d(kSize / 2.0, kSize * 0.9))
                .norm(),
            1e-9);
}

void ExpectInitError(const LooseSetup& setup, const std::map<std::string, Eigen::Vector2i>& sizes,
                     const std::map<std::string, FloatImage>& mattes,
                     const std::vector<std::string>& expected) {
  try {
    InitialLooseCameras(setup, sizes, mattes, {});
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "test.json") << error.what();
    for (const std::string& text : expected) {
      EXPECT_NE(std::string(error.what()).find(text), std::string::npos)
          << "'" << text << "' not in: " << error.what();
    }
  }
}

TEST(InitialLooseCamerasTest, RefusesBadInput) {
  const ImageSet truth = OrthographicTruth({0, 90});
  LooseSetup setup = SetupFor(truth, LooseProjection::kOrthographic);
  RandomEngine random(1);
  Click(truth, "base", Eigen::Vector3d::Zero(), 0.0, &random, &setup);
  std::map<std::string, Eigen::Vector2i> sizes = Sizes(setup);
  sizes.erase("o1.png");
  ExpectInitError(setup, sizes, {}, {"photo 'o1.png' is not among the photos"});

  std::map<std::string, FloatImage> mattes = {{"o0.png", FloatImage(kSize, kSize / 2, 1)}};
  ExpectInitError(setup, Sizes(setup), mattes, {"matte of photo 'o0.png'", "400x200"});

  LooseSetup outside = setup;
  outside.points[0].observations[1].point_in_image.x() = kSize + 3;
  ExpectInitError(outside, Sizes(setup), {}, {"point 'base' in photo 'o1.png'", "outside"});

  LooseSetup upside_down = setup;
  Click(truth, "top", Eigen::Vector3d(0, 0, -0.5), 0.0, &random, &upside_down);
  ExpectInitError(upside_down, Sizes(setup), {}, {"photo 'o0.png'", "not above the base"});

  LooseInitOptions options;
  options.matte_threshold = 1.5;
  EXPECT_THROW(InitialLooseCameras(setup, Sizes(setup), {}, options), InputError);
}

// ---- Refinement -------------------------------------------------------------

// Points of a tree-like cloud: base, top and `n` others in a crown.
std::vector<Eigen::Vector3d> CrownPoints(int n, RandomEngine* random) {
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 5)};
  for (int i = 0; i < n; ++i) {
    points.emplace_back(random->Uniform(-1.8, 1.8), random->Uniform(-1.8, 1.8),
                        random->Uniform(1.5, 4.8));
  }
  return points;
}

struct Scenario {
  ImageSet truth;
  LooseSetup setup;
};

// The truth, and a set-up whose azimuths are off by `offsets` (degrees) and
// whose points were clicked with `sigma` px of noise.
Scenario MakeScenario(const ImageSet& truth, LooseProjection projection,
                      const std::vector<double>& offsets, int num_points, double sigma,
                      uint64_t seed) {
  Scenario scenario{truth, SetupFor(truth, projection)};
  scenario.setup.tree_height = 5.0;
  for (size_t i = 0; i < offsets.size(); ++i) scenario.setup.photos[i].azimuth_deg += offsets[i];
  RandomEngine random(seed);
  const std::vector<Eigen::Vector3d> points = CrownPoints(num_points, &random);
  for (size_t i = 0; i < points.size(); ++i) {
    const std::string name = i == 0 ? "base" : i == 1 ? "top" : "p" + std::to_string(i);
    Click(truth, name, points[i], sigma, &random, &scenario.setup);
  }
  return scenario;
}

double MaxRotationErrorDeg(const ImageSet& a, const ImageSet& b) {
  double worst = 0.0;
  for (int v = 0; v < a.NumViews(); ++v) {
    worst = std::max(worst, RotationErrorDeg(a.views[v].cam_from_world.rotation,
                                             b.views[v].cam_from_world.rotation));
  }
  return worst;
}

TEST(RefineLooseCamerasTest, ThreePerspectiveViewsRecoverTheirAzimuths) {
  // The first photo's azimuth is right (it is the gauge); the others are off.
  const Scenario s = MakeScenario(PerspectiveTruth({0, 120, 240}, 8), LooseProjection::kPerspective,
                                  {0, 8, -7}, 12, 0.5, 3);
  const ImageSet initial = InitialLooseCameras(s.setup, Sizes(s.setup), {}, {});
  const LooseRefinement refined = RefineLooseCameras(s.setup, initial, {});
  const LooseRefineSummary& summary = refined.summary;
  const double before = MaxRotationErrorDeg(initial, s.truth);
  const double after = MaxRotationErrorDeg(refined.image_set, s.truth);
  std::printf("%s\nmax rotation error %.2f -> %.2f deg\n", summary.BriefReport().c_str(), before,
              after);
  EXPECT_TRUE(summary.refined);
  EXPECT_EQ(summary.num_points, 14);
  EXPECT_EQ(summary.num_observations, 42);
  // Three views at one elevation fix their azimuths only weakly (with no
  // click noise the error is 0.2 degrees, from the priors).
  EXPECT_GT(before, 6.0);
  EXPECT_LT(after, 2.0);
  EXPECT_GT(summary.rms_before_px, 1.5);
  EXPECT_LT(summary.rms_after_px, 0.6);  // about the click noise
  EXPECT_LE(summary.num_weak_directions, 2);
  EXPECT_NEAR(summary.points_in_world.at("top").z(), 5.0, 1e-12);  // the height gauge
  EXPECT_EQ(summary.points_in_world.at("base"), Eigen::Vector3d::Zero());
  EXPECT_NEAR(summary.cameras[1].angles_refined_deg.x(), 120.0, 2.0);
  EXPECT_NEAR(summary.cameras[0].angles_refined_deg.x(), 0.0, 1e-9);  // held
  // Deterministic.
  const LooseRefinement again = RefineLooseCameras(s.setup, initial, {});
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(again.image_set.views[v].cam_from_world.translation,
              refined.image_set.views[v].cam_from_world.translation);
  }
}

TEST(RefineLooseCamerasTest, TwoOrthographicViewsWarnThatTheirAngleIsFree) {
  const Scenario s =
      MakeScenario(OrthographicTruth({0, 90}), LooseProjection::kOrthographic, {0, 6}, 8, 0.5, 4);
  const ImageSet initial = InitialLooseCameras(s.setup, Sizes(s.setup), {}, {});
  const LooseRefinement refined = RefineLooseCameras(s.setup, initial, {});
  std::printf("%s\n", refined.summary.BriefReport().c_str());
  // The angle between the views is not observable: it stays at the prior.
  EXPECT_NEAR(refined.summary.cameras[1].angles_refined_deg.x(), 96.0, 1.0);
  EXPECT_GT(refined.summary.num_weak_directions, 2);
  bool warned = false;
  for (const std::string& warning : refined.summary.warnings) {
    warned |= warning.find("two orthographic views") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(RefineLooseCamerasTest, WithoutPointsTheCamerasAreUnchanged) {
  const ImageSet truth = OrthographicTruth({0, 90});
  const LooseSetup setup = SetupFor(truth, LooseProjection::kOrthographic);
  const ImageSet initial = InitialLooseCameras(setup, Sizes(setup), {}, {});
  const LooseRefinement refined = RefineLooseCameras(setup, initial, {});
  EXPECT_FALSE(refined.summary.refined);
  ASSERT_EQ(refined.summary.warnings.size(), 1u);
  EXPECT_EQ(refined.image_set.views[1].cam_from_world.translation,
            initial.views[1].cam_from_world.translation);
}

TEST(RefineLooseCamerasTest, ARobustLossLimitsAWrongClick) {
  const Scenario clean = MakeScenario(PerspectiveTruth({0, 120, 240}, 8),
                                      LooseProjection::kPerspective, {0, 5, -5}, 12, 0.5, 5);
  Scenario s = clean;
  s.setup.points[5].observations[2].point_in_image += Eigen::Vector2d(40, -25);  // a mis-click
  const ImageSet initial = InitialLooseCameras(s.setup, Sizes(s.setup), {}, {});
  LooseRefineOptions least_squares;
  least_squares.robust_loss_px = 1e6;
  const double error_clean =
      MaxRotationErrorDeg(RefineLooseCameras(clean.setup, initial, {}).image_set, s.truth);
  const LooseRefinement robust = RefineLooseCameras(s.setup, initial, {});
  const double error_robust = MaxRotationErrorDeg(robust.image_set, s.truth);
  const double error_least_squares =
      MaxRotationErrorDeg(RefineLooseCameras(s.setup, initial, least_squares).image_set, s.truth);
  std::printf("max rotation error: clean %.2f, mis-click %.2f robust, %.2f least squares deg\n",
              error_clean, error_robust, error_least_squares);
  EXPECT_LT(error_robust, 0.2 * error_least_squares);
  EXPECT_LT(error_robust, error_clean + 0.5);
  EXPECT_EQ(robust.summary.worst_observation,
            "point '" + s.setup.points[5].name + "' in photo 'p2.jpg'");
  EXPECT_GT(robust.summary.max_after_px, 30.0);
}

TEST(RefineLooseCamerasTest, RefusesMismatchedCameras) {
  const ImageSet truth = OrthographicTruth({0, 90});
  LooseSetup setup = SetupFor(truth, LooseProjection::kOrthographic);
  RandomEngine random(1);
  Click(truth, "base", Eigen::Vector3d::Zero(), 0.0, &random, &setup);
  ImageSet initial = InitialLooseCameras(setup, Sizes(setup), {}, {});
  setup.photos[1].projection = LooseProjection::kPerspective;
  EXPECT_THROW(RefineLooseCameras(setup, initial, {}), InputError);
  setup.photos[1].projection = LooseProjection::kOrthographic;
  initial.views[1].name = "other.png";
  EXPECT_THROW(RefineLooseCameras(setup, initial, {}), InputError);
  initial.views[1].name = "o1.png";
  initial.views[1].camera_id = 1;  // shared with o0.png
  EXPECT_THROW(RefineLooseCameras(setup, initial, {}), InputError);
  LooseRefineOptions options;
  options.robust_loss_px = 0;
  EXPECT_THROW(RefineLooseCameras(setup, truth, options), InputError);
}

}  // namespace
}  // namespace sylva
