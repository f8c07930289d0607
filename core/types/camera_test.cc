#include "core/types/camera.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

std::vector<Camera> AllModels() {
  return {
      Camera(CameraModel::kOrthographic, 640, 480, {100, 120, 320, 240}),
      Camera(CameraModel::kSimplePinhole, 640, 480, {500, 320, 240}),
      Camera(CameraModel::kPinhole, 640, 480, {500, 520, 321, 239}),
      Camera(CameraModel::kSimpleRadial, 640, 480, {500, 320, 240, -0.08}),
      Camera(CameraModel::kRadial, 640, 480, {500, 320, 240, -0.08, 0.02}),
      Camera(CameraModel::kOpenCV, 640, 480, {500, 510, 322, 238, -0.1, 0.03, 0.001, -0.002}),
  };
}

TEST(CameraTest, ModelNamesRoundTrip) {
  for (const Camera& camera : AllModels()) {
    EXPECT_EQ(ParseCameraModel(CameraModelName(camera.model()), "test"), camera.model());
    EXPECT_EQ(static_cast<int>(camera.params().size()), CameraModelNumParams(camera.model()));
  }
  EXPECT_THROW(ParseCameraModel("FISHEYE", "test"), InputError);
  EXPECT_EQ(CameraModelFromColmapId(4, "x"), CameraModel::kOpenCV);
  EXPECT_THROW(CameraModelFromColmapId(5, "x"), InputError);
}

// Values worked out by hand from COLMAP's camera_models.h formulas.
TEST(CameraTest, MatchesColmapFormulas) {
  const Camera simple(CameraModel::kSimplePinhole, 100, 80, {100, 50, 40});
  EXPECT_TRUE(simple.ImgFromCam({0, 0, 1}).isApprox(Eigen::Vector2d(50, 40)));
  EXPECT_TRUE(simple.ImgFromCam({1, -0.5, 2}).isApprox(Eigen::Vector2d(100, 15)));

  const Camera radial(CameraModel::kSimpleRadial, 100, 80, {100, 50, 40, 0.1});
  // u = 0.5, v = 0: r2 = 0.25, radial = 0.025, u' = 0.5125.
  EXPECT_NEAR(radial.ImgFromCam({0.5, 0, 1}).x(), 50 + 100 * 0.5125, 1e-12);

  const Camera opencv(CameraModel::kOpenCV, 100, 80, {100, 90, 50, 40, 0.1, 0.01, 0.001, 0.002});
  // u = 0.2, v = 0.1: r2 = 0.05, radial = 0.1*0.05 + 0.01*0.0025 = 0.005025,
  // du = 0.2*0.005025 + 2*0.001*0.02 + 0.002*(0.05 + 0.08) = 0.001005 + 0.00004 + 0.00026,
  // dv = 0.1*0.005025 + 2*0.002*0.02 + 0.001*(0.05 + 0.02) = 0.0005025 + 0.00008 + 0.00007.
  const Eigen::Vector2d p = opencv.ImgFromCam({0.2, 0.1, 1});
  EXPECT_NEAR(p.x(), 50 + 100 * (0.2 + 0.001305), 1e-12);
  EXPECT_NEAR(p.y(), 40 + 90 * (0.1 + 0.0006525), 1e-12);
}

TEST(CameraTest, PixelCentresFollowColmap) {
  // Principal point at the image centre: pixels 49 and 50 (centres 49.5, 50.5)
  // are symmetric about the optical axis.
  const Camera camera = Camera::Pinhole(100, 100, 80);
  const Eigen::Vector3d left = camera.CamRayFromImg({49.5, 50}).direction;
  const Eigen::Vector3d right = camera.CamRayFromImg({50.5, 50}).direction;
  EXPECT_NEAR(left.x(), -right.x(), 1e-15);
  EXPECT_NEAR(left.y(), 0.0, 1e-15);
}

TEST(CameraTest, ProjectUnprojectRoundTripEveryModel) {
  RandomEngine rng(7);
  for (const Camera& camera : AllModels()) {
    SCOPED_TRACE(CameraModelName(camera.model()));
    for (int i = 0; i < 1000; ++i) {
      // Pixels inside the image, where the distortion is invertible.
      const Eigen::Vector2d pixel(rng.Uniform(0, camera.width()), rng.Uniform(0, camera.height()));
      const Ray3d ray = camera.CamRayFromImg(pixel);
      EXPECT_NEAR(ray.direction.norm(), 1.0, 1e-12);
      const double depth = rng.Uniform(0.5, 20);
      const Eigen::Vector3d point = ray.origin + depth * ray.direction;
      ASSERT_TRUE(camera.IsInFront(point));
      EXPECT_LT((camera.ImgFromCam(point) - pixel).norm(), 1e-6);
    }
  }
}

TEST(CameraTest, OrthographicRaysAreParallelLines) {
  const Camera camera = Camera::Orthographic(200, 100, 10);
  const Ray3d a = camera.CamRayFromImg({10, 20});
  const Ray3d b = camera.CamRayFromImg({150, 80});
  EXPECT_TRUE(a.direction.isApprox(b.direction));
  EXPECT_TRUE(std::isinf(a.t_min));
  // Depth does not change the projection, even behind the image plane.
  EXPECT_TRUE(camera.ImgFromCam({1, 2, -5}).isApprox(camera.ImgFromCam({1, 2, 7})));
  EXPECT_TRUE(camera.ImgFromCam({1, 2, 0}).isApprox(Eigen::Vector2d(110, 70)));
}

TEST(CameraTest, ScaledCameraMapsPixelsToScaledPixels) {
  for (const Camera& camera : AllModels()) {
    const Camera half = camera.Scaled(0.5, camera.width() / 2, camera.height() / 2);
    const Eigen::Vector3d point(0.3, -0.2, 2.0);
    EXPECT_LT((half.ImgFromCam(point) - 0.5 * camera.ImgFromCam(point)).norm(), 1e-9)
        << CameraModelName(camera.model());
  }
}

TEST(CameraTest, CheckRejectsBadParameters) {
  EXPECT_NO_THROW(Camera::Pinhole(10, 10, 5).Check("ok"));
  EXPECT_THROW(Camera(CameraModel::kPinhole, 10, 10, {1, 2, 3}), InputError);
  EXPECT_THROW(Camera(CameraModel::kPinhole, 0, 10, {1, 1, 5, 5}).Check("x"), InputError);
  EXPECT_THROW(Camera(CameraModel::kPinhole, 10, 10, {-1, 1, 5, 5}).Check("x"), InputError);
}

}  // namespace
}  // namespace sylva
