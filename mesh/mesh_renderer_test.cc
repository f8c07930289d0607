#include "mesh/mesh_renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "core/util/check.h"

namespace sylva {
namespace {

// An axis-aligned rectangle [x0, x1] x [y0, y1] in the plane z = `z`.
TriangleMesh Rectangle(double x0, double x1, double y0, double y1, double z,
                       const Eigen::Vector3f& color = Eigen::Vector3f(0.2f, 0.6f, 0.4f)) {
  TriangleMesh mesh;
  const int material = mesh.AddMaterial({"paint", color, true});
  const int a = mesh.AddVertex(Eigen::Vector3d(x0, y0, z).cast<float>());
  const int b = mesh.AddVertex(Eigen::Vector3d(x1, y0, z).cast<float>());
  const int c = mesh.AddVertex(Eigen::Vector3d(x1, y1, z).cast<float>());
  const int d = mesh.AddVertex(Eigen::Vector3d(x0, y1, z).cast<float>());
  mesh.AddTriangle(a, b, c, material);
  mesh.AddTriangle(a, c, d, material);
  return mesh;
}

double Sum(const FloatImage& image, int channel = 0) {
  double sum = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image.at(x, y, channel);
  return sum;
}

// A pinhole camera at the origin looking along +z: f = 100 px, 128 x 128, so
// a point (x, y, 5) lands at pixel position (64 + 20 x, 64 + 20 y).
TEST(MeshRendererTest, CoverageOfAnAxisAlignedSquareIsExact) {
  // Columns [44, 84.5), rows [44, 84): column 84 is half covered.
  const MeshRenderer renderer(Rectangle(-1.0, 1.025, -1.0, 1.0, 5.0));
  const Camera camera = Camera::Pinhole(128, 128, 100.0);
  const FloatImage coverage = renderer.RenderCoverage(camera, Rigid3d(), 4);
  ASSERT_EQ(coverage.width(), 128);
  ASSERT_EQ(coverage.channels(), 1);
  EXPECT_NEAR(Sum(coverage), 40.5 * 40.0, 1e-3);
  for (int row = 44; row < 84; ++row) {
    EXPECT_FLOAT_EQ(coverage.at(43, row), 0.0f);
    EXPECT_FLOAT_EQ(coverage.at(44, row), 1.0f);
    EXPECT_FLOAT_EQ(coverage.at(83, row), 1.0f);
    EXPECT_NEAR(coverage.at(84, row), 0.5f, 1e-6);
    EXPECT_FLOAT_EQ(coverage.at(85, row), 0.0f);
  }
  EXPECT_FLOAT_EQ(coverage.at(60, 43), 0.0f);
  EXPECT_FLOAT_EQ(coverage.at(60, 84), 0.0f);
}

TEST(MeshRendererTest, CoverageOfATiltedSquareMatchesItsArea) {
  // A square of side 2 rotated by 30 degrees about the optical axis, at z = 5:
  // 40 x 40 px on the image. Error within a tenth of a pixel per unit edge.
  TriangleMesh mesh = Rectangle(-1.0, 1.0, -1.0, 1.0, 0.0);
  const Eigen::AngleAxisf rotation(static_cast<float>(M_PI / 6), Eigen::Vector3f::UnitZ());
  for (Eigen::Vector3f& v : mesh.vertices) v = rotation * v + Eigen::Vector3f(0.013f, 0.21f, 5.0f);
  const MeshRenderer renderer(mesh);
  const FloatImage coverage =
      renderer.RenderCoverage(Camera::Pinhole(128, 128, 100.0), Rigid3d(), 4);
  const double perimeter_px = 4 * 40.0;
  EXPECT_NEAR(Sum(coverage), 1600.0, 0.1 * perimeter_px);
}

TEST(MeshRendererTest, OrthographicRaysAreFullLines) {
  // 10 px per unit; the camera's nominal centre lies beyond the square, which
  // an orthographic camera must see anyway.
  const MeshRenderer renderer(Rectangle(-1.0, 1.0, -1.0, 1.0, 0.0));
  const Camera camera = Camera::Orthographic(64, 64, 10.0);
  for (double z : {10.0, -10.0}) {
    SCOPED_TRACE(z);
    const Rigid3d cam_from_world =
        LookAt(Eigen::Vector3d(0, 0, z), Eigen::Vector3d(0, 0, 2 * z), Eigen::Vector3d::UnitY());
    const FloatImage coverage = renderer.RenderCoverage(camera, cam_from_world, 2);
    EXPECT_NEAR(Sum(coverage), 400.0, 1e-3);
    EXPECT_FLOAT_EQ(coverage.at(32, 32), 1.0f);
  }
}

TEST(MeshRendererTest, RgbaIsStraightAlphaLambertShading) {
  const Eigen::Vector3f color(0.2f, 0.6f, 0.4f);
  const MeshRenderer renderer(Rectangle(-1.0, 1.025, -1.0, 1.0, 5.0, color));
  MeshRenderOptions options;
  options.ambient = 0.25f;
  // The light 60 degrees off the square's normal: |cos| = 0.5, either side.
  options.light_direction = Eigen::Vector3f(std::sqrt(3.0f) / 2, 0.0f, -0.5f);
  const FloatImage rgba = renderer.RenderRgba(Camera::Pinhole(128, 128, 100.0), Rigid3d(), options);
  ASSERT_EQ(rgba.channels(), 4);
  const float shading = 0.25f + 0.75f * 0.5f;
  for (int col : {50, 84}) {  // inside, and half covered on the edge
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgba.at(col, 60, c), shading * color[c], 1e-5);
  }
  EXPECT_FLOAT_EQ(rgba.at(50, 60, 3), 1.0f);
  EXPECT_NEAR(rgba.at(84, 60, 3), 0.5f, 1e-6);
  for (int c = 0; c < 4; ++c) EXPECT_FLOAT_EQ(rgba.at(10, 10, c), 0.0f);
  // The same sampling as RenderCoverage.
  const FloatImage coverage =
      renderer.RenderCoverage(Camera::Pinhole(128, 128, 100.0), Rigid3d(), 4);
  EXPECT_EQ(rgba.Channel(3).values(), coverage.values());
}

TEST(MeshRendererTest, FollowsTheCameraDistortion) {
  // With barrel/pincushion distortion the covered area changes; the rendered
  // coverage must match a dense analytic sampling through the same camera.
  const Camera camera(CameraModel::kSimpleRadial, 96, 96, {80.0, 48.0, 48.0, 0.15});
  const double half = 1.2, z = 4.0;
  const MeshRenderer renderer(Rectangle(-half, half, -half, half, z));
  const FloatImage coverage = renderer.RenderCoverage(camera, Rigid3d(), 4);
  double expected = 0;
  constexpr int kDense = 8;
  for (int row = 0; row < camera.height(); ++row) {
    for (int col = 0; col < camera.width(); ++col) {
      for (int t = 0; t < kDense; ++t) {
        for (int s = 0; s < kDense; ++s) {
          const Eigen::Vector2d xy = camera.CamFromImg(
              Eigen::Vector2d(col + (s + 0.5) / kDense, row + (t + 0.5) / kDense));
          if (std::abs(xy.x() * z) <= half && std::abs(xy.y() * z) <= half) expected += 1.0;
        }
      }
    }
  }
  expected /= kDense * kDense;
  const double undistorted_area = std::pow(2 * half / z * 80.0, 2);
  EXPECT_GT(std::abs(expected - undistorted_area), 50.0);  // distortion matters here
  EXPECT_NEAR(Sum(coverage), expected, 0.1 * 4 * std::sqrt(expected));
}

TEST(MeshRendererTest, DeterministicAndCastRay) {
  const MeshRenderer renderer(Rectangle(-1.0, 1.0, -1.0, 1.0, 5.0));
  const Camera camera = Camera::Pinhole(64, 48, 50.0);
  const Rigid3d cam_from_world(Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY())),
                               Eigen::Vector3d(0.1, 0.0, 0.5));
  const FloatImage a = renderer.RenderRgba(camera, cam_from_world, MeshRenderOptions());
  const FloatImage b = renderer.RenderRgba(camera, cam_from_world, MeshRenderOptions());
  EXPECT_EQ(a.values(), b.values());
  EXPECT_EQ(renderer.NumTriangles(), 2);

  Ray3d ray;
  ray.direction = Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(renderer.CastRay(ray), 5.0, 1e-5);
  ray.origin = Eigen::Vector3d(0.0, 0.0, 8.0);
  EXPECT_TRUE(std::isinf(renderer.CastRay(ray)));  // behind the origin
  ray.t_min = -std::numeric_limits<double>::infinity();
  EXPECT_NEAR(renderer.CastRay(ray), -3.0, 1e-5);  // a full line sees it
}

// A closed, bumpy ball (shared vertices) and 400 small loose triangles
// around it (unshared, as baked leaves): edges of every slope and size.
TriangleMesh BallAndLeaves() {
  TriangleMesh mesh;
  const int bark = mesh.AddMaterial({"bark", Eigen::Vector3f(0.5f, 0.3f, 0.2f), true});
  const int leaf = mesh.AddMaterial({"leaf", Eigen::Vector3f(0.1f, 0.7f, 0.2f), true});
  constexpr int kRings = 24, kSegments = 40;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(0.9, 1.1);
  const int north = mesh.AddVertex(Eigen::Vector3f(0, 0, 1));
  for (int r = 1; r < kRings; ++r) {
    const double theta = M_PI * r / kRings;
    for (int s = 0; s < kSegments; ++s) {
      const double phi = 2 * M_PI * s / kSegments, radius = jitter(rng);
      mesh.AddVertex(Eigen::Vector3d(radius * std::sin(theta) * std::cos(phi),
                                     radius * std::sin(theta) * std::sin(phi),
                                     radius * std::cos(theta))
                         .cast<float>());
    }
  }
  const int south = mesh.AddVertex(Eigen::Vector3f(0, 0, -1));
  const auto at = [](int r, int s) { return 1 + (r - 1) * kSegments + (s % kSegments); };
  for (int s = 0; s < kSegments; ++s) {
    mesh.AddTriangle(north, at(1, s), at(1, s + 1), bark);
    mesh.AddTriangle(south, at(kRings - 1, s + 1), at(kRings - 1, s), bark);
    for (int r = 1; r + 1 < kRings; ++r) {
      mesh.AddTriangle(at(r, s), at(r + 1, s), at(r + 1, s + 1), bark);
      mesh.AddTriangle(at(r, s), at(r + 1, s + 1), at(r, s + 1), bark);
    }
  }
  std::uniform_real_distribution<double> place(-1.6, 1.6), size(-0.08, 0.08);
  for (int k = 0; k < 400; ++k) {
    const Eigen::Vector3d center(place(rng), place(rng), place(rng));
    int corners[3];
    for (int& c : corners) {
      c = mesh.AddVertex((center + Eigen::Vector3d(size(rng), size(rng), size(rng))).cast<float>());
    }
    mesh.AddTriangle(corners[0], corners[1], corners[2], leaf);
  }
  return mesh;
}

// Share of pixels whose values differ by more than 1e-6 in any channel.
double ShareDiffering(const FloatImage& a, const FloatImage& b) {
  EXPECT_EQ(a.values().size(), b.values().size());
  int differing = 0;
  for (int y = 0; y < a.height(); ++y) {
    for (int x = 0; x < a.width(); ++x) {
      bool differs = false;
      for (int c = 0; c < a.channels(); ++c)
        differs |= std::abs(a.at(x, y, c) - b.at(x, y, c)) > 1e-6;
      differing += differs ? 1 : 0;
    }
  }
  return static_cast<double>(differing) / (a.width() * a.height());
}

TEST(MeshRendererTest, RasterizedSamplesAreTheRays) {
  const MeshRenderer renderer(BallAndLeaves());
  MeshRenderOptions rasterized, cast;
  cast.method = MeshRenderMethod::kRayCast;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const std::pair<Camera, Rigid3d> views[] = {
      {Camera::Pinhole(96, 80, 70.0),
       LookAt(Eigen::Vector3d(4.5, 1.0, 0.8), Eigen::Vector3d::Zero(), up)},
      {Camera(CameraModel::kPinhole, 64, 64, {90.0, 80.0, 30.0, 34.0}),
       LookAt(Eigen::Vector3d(-2.0, -3.5, 2.5), Eigen::Vector3d(0.1, 0.0, 0.2), up)},
      {Camera::Orthographic(72, 72, 18.0),
       LookAt(Eigen::Vector3d(0.0, 0.5, 0.0), Eigen::Vector3d(1.0, 0.5, 0.1), up)}};
  for (const auto& [camera, pose] : views) {
    SCOPED_TRACE(CameraModelName(camera.model()));
    for (int samples : {1, 3}) {
      const FloatImage fast = renderer.RenderCoverage(camera, pose, samples);
      const FloatImage rays =
          renderer.RenderCoverage(camera, pose, samples, MeshRenderMethod::kRayCast);
      EXPECT_GT(Sum(fast), 0.1 * camera.width() * camera.height());
      // Only samples on an edge, to float precision, may differ (none here).
      EXPECT_LE(ShareDiffering(fast, rays), 0.001);
      EXPECT_NEAR(Sum(fast), Sum(rays), 0.5);
      rasterized.samples_per_axis = cast.samples_per_axis = samples;
      // The nearest triangle may differ where leaves cross the ball or each
      // other (depths equal to Embree's float precision): 0.1-0.2 % here.
      EXPECT_LE(ShareDiffering(renderer.RenderRgba(camera, pose, rasterized),
                               renderer.RenderRgba(camera, pose, cast)),
                0.004);
    }
  }
  // Coverage and picture from one pass: the coverage as RenderCoverage, the
  // picture as RenderRgba through the camera scaled 2x (its samples are the
  // coverage's), up to crossings as above; by rays, the same.
  for (MeshRenderMethod method : {MeshRenderMethod::kAuto, MeshRenderMethod::kRayCast}) {
    const auto& [camera, pose] = views[0];
    MeshRenderOptions shading;
    shading.method = method;
    const MeshRenderer::CoverageAndRgba both =
        renderer.RenderCoverageAndRgba(camera, pose, 4, 2, shading);
    EXPECT_EQ(both.coverage.values(), renderer.RenderCoverage(camera, pose, 4, method).values());
    shading.samples_per_axis = 2;
    const Camera larger = camera.Scaled(2.0, 2 * camera.width(), 2 * camera.height());
    EXPECT_LE(ShareDiffering(both.rgba, renderer.RenderRgba(larger, pose, shading)), 0.004);
    EXPECT_TRUE(renderer.RenderCoverageAndRgba(camera, pose, 4, 0, shading).rgba.empty());
    EXPECT_THROW(renderer.RenderCoverageAndRgba(camera, pose, 4, 3, shading), InputError);
  }
  // A camera inside the leaves' cloud sees some behind it: rays are cast.
  const Camera camera = Camera::Pinhole(48, 48, 30.0);
  const Rigid3d inside = LookAt(Eigen::Vector3d(1.4, 0.0, 0.0), Eigen::Vector3d::Zero(), up);
  EXPECT_EQ(renderer.RenderCoverage(camera, inside, 2).values(),
            renderer.RenderCoverage(camera, inside, 2, MeshRenderMethod::kRayCast).values());
}

// Coverage by one ray per sample through MeshRenderer::CastRay, every pixel.
FloatImage CoverageByCastRays(const MeshRenderer& renderer, const Camera& camera,
                              const Rigid3d& cam_from_world, int samples_per_axis) {
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Matrix3d rotation = world_from_cam.rotation.toRotationMatrix();
  FloatImage coverage(camera.width(), camera.height(), 1);
  for (int row = 0; row < camera.height(); ++row) {
    for (int col = 0; col < camera.width(); ++col) {
      int hits = 0;
      for (int t = 0; t < samples_per_axis; ++t) {
        for (int s = 0; s < samples_per_axis; ++s) {
          Ray3d ray = camera.CamRayFromImg(Eigen::Vector2d(col + (s + 0.5) / samples_per_axis,
                                                           row + (t + 0.5) / samples_per_axis));
          ray.origin = rotation * ray.origin + world_from_cam.translation;
          ray.direction = rotation * ray.direction;
          hits += std::isfinite(renderer.CastRay(ray)) ? 1 : 0;
        }
      }
      coverage.at(col, row) = static_cast<float>(hits) / (samples_per_axis * samples_per_axis);
    }
  }
  return coverage;
}

TEST(MeshRendererTest, RaysAreCastOnlyWhereTheMeshsBoundsReach) {
  // Rays are traced only for pixels whose rays may meet the mesh's bounds
  // (distorted cameras, and rays asked for): every other pixel stays empty,
  // as its rays would leave it. A small ball off the image's centre, where
  // a strong distortion bends the bounds' outline most, and a camera with a
  // corner of the bounds behind it (every pixel traced): the same coverage
  // as one cast ray per sample over the whole image.
  TriangleMesh ball = BallAndLeaves();
  for (Eigen::Vector3f& v : ball.vertices) v = 0.3f * v + Eigen::Vector3f(0.9f, -0.6f, 0.2f);
  const MeshRenderer renderer(ball);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Rigid3d pose = LookAt(Eigen::Vector3d(5.0, 1.0, 0.8), Eigen::Vector3d::Zero(), up);
  const std::pair<Camera, Rigid3d> views[] = {
      {Camera(CameraModel::kOpenCV, 96, 80, {70.0, 72.0, 47.0, 41.0, -0.25, 0.06, 0.004, -0.003}),
       pose},
      {Camera(CameraModel::kSimpleRadial, 90, 90, {75.0, 45.0, 45.0, 0.2}), pose},
      {Camera::Pinhole(96, 80, 70.0), pose},
      {Camera::Orthographic(72, 72, 18.0), pose},
      // Between the ball and the leaves around it, wide-angle.
      {Camera(CameraModel::kSimpleRadial, 48, 48, {12.0, 24.0, 24.0, -0.05}),
       LookAt(Eigen::Vector3d(0.9, -1.02, 0.2), Eigen::Vector3d(0.9, 3.0, 0.2), up)}};
  // A cube fills its bounds: under barrel distortion its edges bow out of
  // the rectangle around its corners' images.
  TriangleMesh cube;
  const int paint = cube.AddMaterial({"paint", Eigen::Vector3f(0.5f, 0.5f, 0.5f), true});
  for (int k = 0; k < 8; ++k) {
    cube.AddVertex(
        Eigen::Vector3f(k & 1 ? 1.8f : -1.5f, k & 2 ? 1.6f : -1.7f, k & 4 ? 4.0f : 3.0f));
  }
  for (const auto& [a, b, c, d] : std::vector<std::array<int, 4>>{
           {0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}}) {
    cube.AddTriangle(a, b, c, paint);
    cube.AddTriangle(a, c, d, paint);
  }
  const MeshRenderer cube_renderer(cube);
  const Camera barrel(CameraModel::kOpenCV, 160, 150, {60.0, 60.0, 81.0, 74.0, -0.3, 0.05, 0, 0});
  const FloatImage cube_coverage =
      cube_renderer.RenderCoverage(barrel, Rigid3d(), 2, MeshRenderMethod::kRayCast);
  EXPECT_GT(Sum(cube_coverage), 1000.0);
  EXPECT_LT(Sum(cube_coverage), 0.5 * barrel.width() * barrel.height());
  EXPECT_EQ(cube_coverage.values(),
            CoverageByCastRays(cube_renderer, barrel, Rigid3d(), 2).values());
  for (const auto& [camera, view_pose] : views) {
    SCOPED_TRACE(CameraModelName(camera.model()));
    const FloatImage coverage =
        renderer.RenderCoverage(camera, view_pose, 2, MeshRenderMethod::kRayCast);
    const double covered = Sum(coverage);
    EXPECT_GT(covered, 10.0);
    EXPECT_LT(covered, 0.5 * camera.width() * camera.height());
    EXPECT_EQ(coverage.values(), CoverageByCastRays(renderer, camera, view_pose, 2).values());
    MeshRenderOptions cast;
    cast.method = MeshRenderMethod::kRayCast;
    cast.samples_per_axis = 2;
    EXPECT_EQ(renderer.RenderRgba(camera, view_pose, cast).Channel(3).values(), coverage.values());
  }
}

// A renderer keeps the undistorted sample points of a distorted camera it
// renders with more than once (the report renders every view of a photo
// set with one camera): each render is the same, to the bit, as a fresh
// renderer's, which undistorts every sample; a camera differing in one
// distortion coefficient, or in the samples per pixel, is not served by
// another's points.
TEST(MeshRendererTest, ViewsSharingADistortedCameraRenderAsAlone) {
  TriangleMesh ball = BallAndLeaves();
  const MeshRenderer shared(ball);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Camera camera(CameraModel::kOpenCV, 96, 80,
                      {70.0, 72.0, 47.0, 41.0, -0.25, 0.06, 0.004, -0.003});
  std::vector<double> params = camera.params();
  params[4] = -0.2;
  const Camera other(CameraModel::kOpenCV, 96, 80, params);
  MeshRenderOptions options;
  options.method = MeshRenderMethod::kRayCast;
  options.samples_per_axis = 2;
  const std::vector<std::pair<const Camera*, int>> renders = {
      {&camera, 2}, {&camera, 2}, {&camera, 2}, {&other, 2}, {&other, 2},
      {&camera, 3}, {&camera, 3}, {&other, 2},  {&camera, 2}};
  for (size_t k = 0; k < renders.size(); ++k) {
    const auto& [view_camera, samples] = renders[k];
    SCOPED_TRACE(k);
    const double angle = 0.7 * static_cast<double>(k);
    const Rigid3d pose = LookAt(Eigen::Vector3d(5.0 * std::cos(angle), 5.0 * std::sin(angle), 0.8),
                                Eigen::Vector3d::Zero(), up);
    options.samples_per_axis = samples;
    const FloatImage rgba = shared.RenderRgba(*view_camera, pose, options);
    const FloatImage alone = MeshRenderer(ball).RenderRgba(*view_camera, pose, options);
    EXPECT_GT(Sum(rgba, 3), 10.0);
    EXPECT_EQ(rgba.values(), alone.values());
  }
}

TEST(MeshRendererTest, EmptyMeshAndBadOptions) {
  const MeshRenderer renderer{TriangleMesh()};
  const FloatImage coverage = renderer.RenderCoverage(Camera::Pinhole(8, 8, 10.0), Rigid3d(), 2);
  EXPECT_EQ(Sum(coverage), 0.0);
  MeshRenderOptions options;
  options.samples_per_axis = 0;
  EXPECT_THROW(renderer.RenderRgba(Camera::Pinhole(8, 8, 10.0), Rigid3d(), options), InputError);
  options = MeshRenderOptions();
  options.light_direction.setZero();
  EXPECT_THROW(options.Check(), InputError);
}

}  // namespace
}  // namespace sylva
