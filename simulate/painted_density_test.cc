#include "simulate/painted_density.h"

#include <gtest/gtest.h>

#include "core/geometry/rigid3.h"
#include "simulate/skeleton_consolidation.h"
#include "simulate/skeleton_pruning.h"

namespace sylva {
namespace {

constexpr double kVoxel = 0.1;

// A trunk (100 strands) to 8 m with a branch inside the crown (x < 0.5) and
// a thin stick out of it to (4, 0, 6), and a thin twig leaving the trunk's
// foot; density along the trunk and the inside branch, and a ball of it
// around the stick's tip (the painted region).
struct Scene {
  SkeletonGraph skeleton;
  DensityGrid density{kVoxel, Eigen::Vector3d::Zero()};
  ImageSet views;
  std::vector<FloatImage> mattes;  // the crown: world x < 0.5, and the ball
  std::vector<FloatImage> painted;
  Eigen::Vector3d ball{4, 0, 6};
};

void AddDensity(const Eigen::Vector3d& a, const Eigen::Vector3d& b, DensityGrid* density) {
  const int steps = static_cast<int>((b - a).norm() / (0.5 * kVoxel)) + 1;
  for (int s = 0; s <= steps; ++s) {
    const Eigen::Vector3d p = a + (b - a) * (double(s) / steps);
    density->SetValue(density->IndexFromWorld(p).array().round().cast<int>(), 0.5f);
  }
}

// One orthographic view along +y, 10 pixels per metre.
void AddFrontView(Scene* scene) {
  scene->views.cameras[1] = Camera(CameraModel::kOrthographic, 100, 100, {10, 10, 50, 50});
  View view;
  view.image_id = 1;
  view.name = "front.png";
  view.camera_id = 1;
  view.cam_from_world = LookAt({0, -10, 5}, {0, 0, 5}, Eigen::Vector3d::UnitZ());
  scene->views.views.push_back(view);
}

// Sets `image` to 1 within `radius` pixels of the projection of `point`.
void PaintDisc(const ImageSet& views, const Eigen::Vector3d& point, double radius,
               FloatImage* image) {
  Eigen::Vector2d centre;
  ASSERT_TRUE(views.Project(0, point, &centre));
  for (int y = 0; y < image->height(); ++y) {
    for (int x = 0; x < image->width(); ++x) {
      if ((Eigen::Vector2d(x + 0.5, y + 0.5) - centre).norm() <= radius) image->at(x, y) = 1.0f;
    }
  }
}

Scene MakeScene() {
  Scene scene;
  SkeletonGraph& s = scene.skeleton;
  const int root = s.AddNode({0, 0, 0}, 0, -1, 0);
  const int fork = s.AddNode({0, 0, 4}, 0, root, 0);
  s.AddNode({0, 0, 8}, 0, fork, 0);   // 2: trunk top
  s.AddNode({-2, 0, 6}, 0, fork, 1);  // 3: the branch inside the crown
  const int stick = s.AddNode({1, 0, 5}, 0, fork, 1);
  s.AddNode({4, 0, 6}, 0, stick, 1);     // 5: the stick's tip, in the ball
  s.AddNode({0.5, 0, 0.2}, 0, root, 1);  // 6: the twig at the foot
  const int strands[] = {100, 98, 93, 3, 2, 2, 2};
  for (int i = 0; i < s.NumNodes(); ++i) s.nodes[i].strands = strands[i];
  s.AssignOrders();
  AddDensity({0, 0, 0}, {0, 0, 8}, &scene.density);
  AddDensity({0, 0, 4}, {-2, 0, 6}, &scene.density);
  AddDensity({0, 0, 0}, {0.5, 0, 0.2}, &scene.density);
  AddDensity(scene.ball - Eigen::Vector3d(0.3, 0, 0), scene.ball + Eigen::Vector3d(0.3, 0, 0),
             &scene.density);
  AddFrontView(&scene);
  FloatImage matte(100, 100, 1, 0.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 55; ++x) matte.at(x, y) = 1.0f;  // pixel x < 55 <-> world x < 0.5
  FloatImage painted(100, 100, 1, 0.0f);
  PaintDisc(scene.views, scene.ball, 4.0, &painted);
  for (size_t i = 0; i < matte.values().size(); ++i) {
    matte.values()[i] = std::max(matte.values()[i], painted.values()[i]);
  }
  scene.mattes = {matte};
  scene.painted = {painted};
  return scene;
}

TEST(PaintedDensityTest, PaintedDensityIsWherePaintAndDensityMeet) {
  const Scene scene = MakeScene();
  const PaintedDensity painted(scene.density, scene.views, scene.painted);
  EXPECT_TRUE(painted.Any());
  EXPECT_TRUE(painted.Contains(scene.ball));
  // Painted pixels, but no density there (in front of the ball).
  EXPECT_FALSE(painted.Contains(scene.ball + Eigen::Vector3d(0, -3, 0.0)));
  // Density, but not painted.
  EXPECT_FALSE(painted.Contains({-2, 0, 6}));
  // The stick and every ancestor of its tip carry the painted density.
  const std::vector<char> carrying = painted.CarryingWood(scene.skeleton);
  EXPECT_EQ(carrying, (std::vector<char>{1, 1, 0, 0, 1, 1, 0}));
  // Nothing painted: nothing carries it.
  const std::vector<FloatImage> none = {FloatImage(100, 100, 1, 0.0f)};
  const PaintedDensity unpainted(scene.density, scene.views, none);
  EXPECT_FALSE(unpainted.Any());
  EXPECT_EQ(unpainted.CarryingWood(scene.skeleton), std::vector<char>(7, 0));
}

TEST(PaintedDensityTest, MattePruningKeepsTheStickToPaintedDensity) {
  const Scene scene = MakeScene();
  MattePruningSummary summary;
  // Unpainted, the stick leaves the matte for most of its length and goes.
  const SkeletonGraph pruned = PruneBranchesOutsideMattes(scene.skeleton, scene.views, scene.mattes,
                                                          MattePruningOptions(), &summary);
  EXPECT_EQ(summary.removed_axes, 1);
  EXPECT_EQ(pruned.NumNodes(), 5);
  const PaintedDensity painted(scene.density, scene.views, scene.painted);
  const SkeletonGraph kept = PruneBranchesOutsideMattes(scene.skeleton, scene.views, scene.mattes,
                                                        MattePruningOptions(), &summary, &painted);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.removed_axes, 0);
  EXPECT_EQ(summary.painted_axes, 1);
  EXPECT_EQ(kept.NumNodes(), 7);
  EXPECT_NE(summary.BriefReport().find("1 kept: they carry painted density"), std::string::npos);
}

TEST(PaintedDensityTest, ConsolidationKeepsTheBareStickToPaintedDensity) {
  Scene scene = MakeScene();
  ConsolidationOptions options;
  options.redundancy_fraction = 0;  // steps 2 and 3 only
  options.min_support = 0;
  ConsolidationSummary summary;
  const SkeletonGraph plain = ConsolidateSkeleton(scene.skeleton, scene.density, options, &summary);
  EXPECT_EQ(summary.bare_axes, 1);  // the stick
  EXPECT_EQ(summary.base_axes, 1);  // the twig at the foot
  EXPECT_EQ(plain.NumNodes(), 4);
  // Paint the foot's twig too: both are kept, nothing else changes.
  PaintDisc(scene.views, {0.5, 0, 0.2}, 2.0, &scene.painted[0]);
  const PaintedDensity painted(scene.density, scene.views, scene.painted);
  const SkeletonGraph kept =
      ConsolidateSkeleton(scene.skeleton, scene.density, options, &summary, &painted);
  SCOPED_TRACE(summary.BriefReport());
  EXPECT_EQ(summary.bare_axes + summary.base_axes, 0);
  EXPECT_EQ(summary.painted_axes, 2);
  EXPECT_EQ(kept.NumNodes(), 7);
  EXPECT_NEAR(kept.TotalLength(), scene.skeleton.TotalLength(), 1e-9);
}

}  // namespace
}  // namespace sylva
