// Loose registration (thesis 3.3) on synthetic trees with known cameras:
//  - clicked points (the base, the top and branch tips of the true tree,
//    projected into the true cameras plus 1 px of noise) refine cameras whose
//    given azimuths are off by up to +-10 degrees: pose errors before and
//    after over 10 seeds, for 2 and 4 views, perspective and orthographic;
//  - the thesis' set-up, two orthographic views at a right angle and no
//    clicks: cameras from the mattes alone give a density whose projections
//    match the mattes (input and held-out views), as the true cameras do.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/util/random.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "reconstruct/registration/loose_registration.h"
#include "ui/pipeline/report.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int kNumSeeds = 10;
// Branch tips clicked (one per azimuth sector around the trunk).
constexpr int kNumTips = 8;
// What the user gets wrong: azimuths within +-10 degrees, elevations within
// +-2 degrees, focal lengths within +-15 %; clicks have 1 px of noise.
constexpr double kAzimuthErrorDeg = 10.0;
constexpr double kElevationErrorDeg = 2.0;
constexpr double kFocalError = 0.15;
constexpr double kClickSigmaPx = 1.0;
// Skeleton nodes used to measure how far the estimated cameras put the tree
// in the images (every n-th node).
constexpr int kImageErrorNodeStride = 10;

struct Config {
  const char* label;
  SyntheticCameraKind camera;
  int num_generated;          // views MakeSyntheticCameras places
  std::vector<int> selected;  // the ones used as photos
};

// 2 perspective photos at a right angle (views 0 and 1 of a 4-view ring);
// 2 orthographic photos at a right angle (the thesis); 4 of each.
const std::vector<Config>& Configs() {
  static const std::vector<Config> configs = {
      {"2 orthographic", SyntheticCameraKind::kOrthographic, 2, {0, 1}},
      {"4 orthographic", SyntheticCameraKind::kOrthographic, 4, {0, 1, 2, 3}},
      {"2 perspective", SyntheticCameraKind::kPinhole, 4, {0, 1}},
      {"4 perspective", SyntheticCameraKind::kPinhole, 4, {0, 1, 2, 3}},
  };
  return configs;
}

struct Truth {
  ImageSet cameras;
  SkeletonGraph skeleton;
  double height = 0.0;                                          // of the highest mesh vertex
  std::vector<std::pair<std::string, Eigen::Vector3d>> points;  // to click
};

// The tip farthest from the trunk in each of kNumTips azimuth sectors.
std::vector<Eigen::Vector3d> SectorTips(const SkeletonGraph& skeleton) {
  std::vector<Eigen::Vector3d> best(kNumTips);
  std::vector<double> radius(kNumTips, -1.0);
  for (int tip : skeleton.Tips()) {
    const Eigen::Vector3d& p = skeleton.nodes[tip].position;
    const double angle = std::atan2(p.y(), p.x()) + M_PI;
    const int sector = std::min(kNumTips - 1, static_cast<int>(angle / (2 * M_PI) * kNumTips));
    if (p.head<2>().norm() > radius[sector]) {
      radius[sector] = p.head<2>().norm();
      best[sector] = p;
    }
  }
  std::vector<Eigen::Vector3d> tips;
  for (int s = 0; s < kNumTips; ++s) {
    if (radius[s] >= 0) tips.push_back(best[s]);
  }
  return tips;
}

// The tree's highest point (a leaf at the top of the crown).
Eigen::Vector3d HighestVertex(const TriangleMesh& mesh) {
  Eigen::Vector3d top = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& vertex : mesh.vertices) {
    if (vertex.z() > top.z()) top = vertex.cast<double>();
  }
  return top;
}

Truth MakeTruth(const Config& config, uint64_t seed) {
  SyntheticDatasetOptions options;
  options.seed = seed;
  options.camera = config.camera;
  options.num_views = config.num_generated;
  options.num_held_out = 0;
  const SyntheticTree tree = GenerateSyntheticTree(options.tree, seed);
  const ImageSet all = MakeSyntheticCameras(options, tree.mesh);
  Truth truth;
  truth.cameras.cameras = all.cameras;
  for (int v : config.selected) truth.cameras.views.push_back(all.views[v]);
  truth.skeleton = tree.skeleton;
  const Eigen::Vector3d top = HighestVertex(tree.mesh);
  truth.height = top.z();
  truth.points = {{"base", tree.skeleton.nodes[tree.skeleton.RootIdx()].position}, {"top", top}};
  const std::vector<Eigen::Vector3d> tips = SectorTips(tree.skeleton);
  for (size_t i = 0; i < tips.size(); ++i) {
    truth.points.emplace_back("tip" + std::to_string(i + 1), tips[i]);
  }
  return truth;
}

// The user's view of it: perturbed angles and focal lengths, noisy clicks;
// with more than 2 photos every point, the base and top too, is hidden in
// one of them (where the base or the top is missing, the initial camera
// guesses it: InitialLooseCameras gets no mattes here).
LooseSetup MakeSetup(const Truth& truth, bool perspective, uint64_t seed) {
  RandomEngine random(DeriveSeed(seed, 17));
  LooseSetup setup;
  setup.source = "synthetic";
  setup.tree_height = truth.height;
  setup.units = "m";
  for (const View& view : truth.cameras.views) {
    const Eigen::Vector3d angles = LooseAnglesDeg(view.cam_from_world.rotation);
    LoosePhoto photo;
    photo.name = view.name;
    photo.azimuth_deg = angles.x() + random.Uniform(-kAzimuthErrorDeg, kAzimuthErrorDeg);
    photo.elevation_deg = angles.y() + random.Uniform(-kElevationErrorDeg, kElevationErrorDeg);
    photo.projection = perspective ? LooseProjection::kPerspective : LooseProjection::kOrthographic;
    if (perspective) {
      photo.focal_length_px = truth.cameras.CameraOf(view).FocalLengthX() *
                              (1.0 + random.Uniform(-kFocalError, kFocalError));
    }
    setup.photos.push_back(photo);
  }
  const int num_views = truth.cameras.NumViews();
  for (const auto& [name, position] : truth.points) {
    const int hidden = num_views > 2 ? static_cast<int>(random.UniformInt(num_views)) : -1;
    LoosePoint point;
    point.name = name;
    for (int v = 0; v < num_views; ++v) {
      Eigen::Vector2d pixel;
      EXPECT_TRUE(truth.cameras.Project(v, position, &pixel));
      pixel += Eigen::Vector2d(random.Normal(0, kClickSigmaPx), random.Normal(0, kClickSigmaPx));
      if (v != hidden) point.observations.push_back({v, pixel});
    }
    setup.points.push_back(point);
  }
  return setup;
}

// Errors of estimated cameras, each the worst over the views, after turning
// the estimate about the vertical axis onto the truth (the first photo's
// azimuth is the user's, so the whole estimate is turned by its error).
struct PoseErrors {
  double rotation_deg = 0.0;
  // Perspective: camera centre error in % of the true distance to the tree's
  // middle; orthographic: image-plane offset error in % of the tree height.
  double position_pct = 0.0;
  double scale_pct = 0.0;  // orthographic scale or focal length, |error| in %
  double image_px = 0.0;   // mean image distance of skeleton nodes, in pixels
};

PoseErrors Compare(const ImageSet& estimate, const Truth& truth) {
  const ImageSet& true_cameras = truth.cameras;
  double sin_sum = 0.0, cos_sum = 0.0;
  for (int v = 0; v < estimate.NumViews(); ++v) {
    const double difference = LooseAnglesDeg(estimate.views[v].cam_from_world.rotation).x() -
                              LooseAnglesDeg(true_cameras.views[v].cam_from_world.rotation).x();
    sin_sum += std::sin(difference * kDegree);
    cos_sum += std::cos(difference * kDegree);
  }
  const Rigid3d estimate_from_true(
      Eigen::Quaterniond(Eigen::AngleAxisd(std::atan2(sin_sum, cos_sum), Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d::Zero());
  ImageSet aligned = estimate;
  PoseErrors errors;
  const Eigen::Vector3d middle(0, 0, 0.5 * truth.height);
  for (int v = 0; v < estimate.NumViews(); ++v) {
    View& view = aligned.views[v];
    view.cam_from_world = view.cam_from_world * estimate_from_true;
    const View& true_view = true_cameras.views[v];
    const Camera& camera = aligned.CameraOf(view);
    errors.rotation_deg = std::max(
        errors.rotation_deg,
        view.cam_from_world.rotation.angularDistance(true_view.cam_from_world.rotation) / kDegree);
    const double position =
        camera.IsOrthographic()
            ? (view.cam_from_world.translation - true_view.cam_from_world.translation)
                      .head<2>()
                      .norm() /
                  truth.height
            : (view.ProjectionCenter() - true_view.ProjectionCenter()).norm() /
                  (true_view.ProjectionCenter() - middle).norm();
    errors.position_pct = std::max(errors.position_pct, 100.0 * position);
    errors.scale_pct = std::max(
        errors.scale_pct,
        100.0 *
            std::abs(camera.FocalLengthX() / true_cameras.CameraOf(true_view).FocalLengthX() - 1));
  }
  double sum = 0.0;
  int count = 0;
  for (int v = 0; v < estimate.NumViews(); ++v) {
    for (int n = 0; n < truth.skeleton.NumNodes(); n += kImageErrorNodeStride) {
      Eigen::Vector2d a, b;
      const Eigen::Vector3d& p = truth.skeleton.nodes[n].position;
      if (aligned.Project(v, p, &a) && true_cameras.Project(v, p, &b)) {
        sum += (a - b).norm();
        ++count;
      }
    }
  }
  errors.image_px = sum / std::max(count, 1);
  return errors;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}
double Max(const std::vector<double>& values) {
  return *std::max_element(values.begin(), values.end());
}

struct Statistics {
  std::vector<double> rotation[2], position[2], scale[2], image[2], rms[2];
  int clicks = 0, points = 0;

  void Add(int i, const PoseErrors& errors) {
    rotation[i].push_back(errors.rotation_deg);
    position[i].push_back(errors.position_pct);
    scale[i].push_back(errors.scale_pct);
    image[i].push_back(errors.image_px);
  }
  void Print(const char* label) const {
    std::printf(
        "%s views, %d seeds, %d points, %d clicks per seed; median / max over seeds of "
        "the worst view, initial -> refined:\n",
        label, kNumSeeds, points, clicks);
    auto line = [](const char* name, const std::vector<double>* values, const char* unit) {
      std::printf("  %-22s %7.2f / %7.2f -> %7.2f / %7.2f %s\n", name, Median(values[0]),
                  Max(values[0]), Median(values[1]), Max(values[1]), unit);
    };
    line("rotation", rotation, "deg");
    line("position", position, "%");
    line("scale / focal", scale, "%");
    line("skeleton in image", image, "px (mean)");
    line("reprojection RMS", rms, "px");
  }
};

Statistics Measure(const Config& config) {
  Statistics statistics;
  const bool perspective = config.camera == SyntheticCameraKind::kPinhole;
  for (uint64_t seed = 1; seed <= kNumSeeds; ++seed) {
    const Truth truth = MakeTruth(config, seed);
    const LooseSetup setup = MakeSetup(truth, perspective, seed);
    std::map<std::string, Eigen::Vector2i> sizes;
    for (const View& view : truth.cameras.views) {
      const Camera& camera = truth.cameras.CameraOf(view);
      sizes[view.name] = Eigen::Vector2i(camera.width(), camera.height());
    }
    const ImageSet initial = InitialLooseCameras(setup, sizes, {}, {});
    const LooseRefinement refined = RefineLooseCameras(setup, initial, {});
    statistics.Add(0, Compare(initial, truth));
    statistics.Add(1, Compare(refined.image_set, truth));
    statistics.rms[0].push_back(refined.summary.rms_before_px);
    statistics.rms[1].push_back(refined.summary.rms_after_px);
    statistics.clicks = refined.summary.num_observations;
    statistics.points = refined.summary.num_points;
  }
  statistics.Print(config.label);
  return statistics;
}

TEST(LooseRegistrationTest, TwoOrthographicViews) {
  const Statistics s = Measure(Configs()[0]);
  // The angle between two orthographic views is not observable (it stays at
  // the given, wrong values), so the rotation error drops only by the
  // elevations' share; base and top are clicked in both, so the initial
  // scale and placement are already right and must stay so.
  EXPECT_LT(Median(s.rotation[1]), 0.9 * Median(s.rotation[0]));
  EXPECT_LT(Median(s.image[1]), Median(s.image[0]) + 0.5);
  EXPECT_LT(Max(s.scale[1]), 1.0);
  EXPECT_LT(Max(s.position[1]), 1.0);
  EXPECT_LT(Median(s.rms[1]), 0.5 * Median(s.rms[0]));
}

TEST(LooseRegistrationTest, FourOrthographicViews) {
  const Statistics s = Measure(Configs()[1]);
  EXPECT_LT(Median(s.rotation[1]), 0.3 * Median(s.rotation[0]));
  EXPECT_LT(Max(s.rotation[1]), 0.5 * Max(s.rotation[0]));
  EXPECT_LT(Median(s.rotation[1]), 1.5);
  EXPECT_LT(Median(s.position[1]), 0.2 * Median(s.position[0]));
  EXPECT_LT(Median(s.scale[1]), 0.2 * Median(s.scale[0]));
  EXPECT_LT(Median(s.image[1]), 0.2 * Median(s.image[0]));
}

TEST(LooseRegistrationTest, TwoPerspectiveViews) {
  const Statistics s = Measure(Configs()[2]);
  // Nearly orthographic (the tree spans ~40 degrees): the angle between two
  // views is only weakly observable.
  EXPECT_LT(Median(s.rotation[1]), 0.6 * Median(s.rotation[0]));
  EXPECT_LT(Median(s.position[1]), 0.8 * Median(s.position[0]));
  EXPECT_LT(Median(s.scale[1]), 0.7 * Median(s.scale[0]));
  EXPECT_LT(Median(s.image[1]), 0.5 * Median(s.image[0]));
}

TEST(LooseRegistrationTest, FourPerspectiveViews) {
  const Statistics s = Measure(Configs()[3]);
  EXPECT_LT(Median(s.rotation[1]), 0.3 * Median(s.rotation[0]));
  EXPECT_LT(Max(s.rotation[1]), 0.5 * Max(s.rotation[0]));
  EXPECT_LT(Median(s.rotation[1]), 2.0);
  EXPECT_LT(Median(s.position[1]), 0.6 * Median(s.position[0]));
  // Focal length and distance trade off (a dolly zoom changes the images
  // little): the focal length improves least.
  EXPECT_LT(Median(s.scale[1]), Median(s.scale[0]));
  EXPECT_LT(Median(s.image[1]), 0.2 * Median(s.image[0]));
}

// `loose` (the input views) followed by the true held-out views of `data`,
// in data.image_set's order.
ImageSet WithTrueHeldOutViews(const ImageSet& loose, const SyntheticDataset& data) {
  ImageSet result = loose;
  const int held_out_camera_id = 1 + result.cameras.rbegin()->first;
  result.cameras[held_out_camera_id] = data.image_set.CameraOf(data.image_set.views.back());
  for (const View& view : data.image_set.views) {
    if (!data.IsHeldOut(view.name)) continue;
    View held_out = view;
    held_out.camera_id = held_out_camera_id;
    result.views.push_back(held_out);
  }
  return result;
}

// The thesis' set-up: two orthographic views at a right angle, no clicks.
// Cameras from the mattes alone, then the density stage, then the density's
// projections against the mattes, in the input views through the loose
// cameras and in held-out views through their true cameras (which tests that
// the loose world frame is the true one: base at the origin, +Z up, metres
// from the known height).
TEST(LooseRegistrationTest, TwoOrthographicViewsFromMattesReconstructTheDensity) {
  SyntheticDatasetOptions options;
  options.seed = 1;
  options.camera = SyntheticCameraKind::kOrthographic;
  options.num_views = 2;
  options.num_held_out = 2;
  const SyntheticDataset data = MakeSyntheticDataset(options);
  const double height = HighestVertex(data.tree.mesh).z();
  LooseSetup setup;
  setup.tree_height = height;
  setup.units = "m";
  std::map<std::string, Eigen::Vector2i> sizes;
  std::map<std::string, FloatImage> mattes;
  const ImageSet input = data.InputImageSet();
  const std::vector<FloatImage> input_mattes = data.InputMattes();
  for (int v = 0; v < input.NumViews(); ++v) {
    const std::string& name = input.views[v].name;
    setup.photos.push_back({name, 90.0 * v, 0, 0, LooseProjection::kOrthographic});
    sizes[name] = Eigen::Vector2i(input_mattes[v].width(), input_mattes[v].height());
    mattes[name] = input_mattes[v];
  }
  LooseInitSummary init_summary;
  const ImageSet loose = InitialLooseCameras(setup, sizes, mattes, {}, &init_summary);
  std::printf("%s\n", init_summary.BriefReport().c_str());
  EXPECT_TRUE(init_summary.warnings.empty());
  // The true cameras: same scale, and the base and top in the same places.
  for (int v = 0; v < 2; ++v) {
    const double true_scale = input.CameraOf(v).FocalLengthX();
    std::printf("  %s: scale %.3f px/m (true %.3f)\n", input.views[v].name.c_str(),
                loose.CameraOf(v).FocalLengthX(), true_scale);
    EXPECT_NEAR(loose.CameraOf(v).FocalLengthX() / true_scale, 1.0, 0.01);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, height)}) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(loose.Project(v, p, &a) && input.Project(v, p, &b));
      EXPECT_LT((a - b).norm(), 2.0) << input.views[v].name << " " << p.transpose();
    }
  }

  // Without the height the world is the same up to scale.
  LooseSetup unknown_height = setup;
  unknown_height.tree_height = 0;
  LooseInitOptions init_options;
  const ImageSet scaled = InitialLooseCameras(unknown_height, sizes, mattes, init_options);
  const double scale = init_options.assumed_tree_height / height;
  for (int v = 0; v < 2; ++v) {
    const Eigen::Vector3d p(1.0, -2.0, 3.0);
    Eigen::Vector2d a, b;
    ASSERT_TRUE(loose.Project(v, p, &a) && scaled.Project(v, scale * p, &b));
    EXPECT_LT((a - b).norm(), 1e-6);
  }

  DensitySummary density_summary;
  const DensityGrid grid =
      ReconstructDensity(loose, input_mattes, DensityOptions(), nullptr, &density_summary);
  ReportOptions report_options;
  report_options.write_images = false;
  const FidelityReport report = ComputeFidelity(grid, WithTrueHeldOutViews(loose, data),
                                                data.mattes, data.HeldOutFlags(), report_options);
  for (const ViewFidelity& view : report.views) {
    std::printf("  %-16s %s IoU %.3f precision %.3f recall %.3f\n", view.name.c_str(),
                view.held_out ? "held-out" : "input   ", view.scores.iou, view.scores.precision,
                view.scores.recall);
    EXPECT_GE(view.scores.iou, view.held_out ? 0.75 : 0.9) << view.name;
  }
  EXPECT_EQ(report.input.num_views, 2);
  EXPECT_EQ(report.held_out.num_views, 2);
}

}  // namespace
}  // namespace sylva
