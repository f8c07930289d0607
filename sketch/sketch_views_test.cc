#include "sketch/sketch_views.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/util/check.h"

namespace sylva {
namespace {

// A lollipop tree on a 200 x 400 canvas: a trunk from the base (100, 380)
// up to (100, 200) and a closed round crown of radius 80 about (100, 130)
// with one branch inside it.
SketchDrawing Lollipop(const std::string& source = "front.svg") {
  SketchDrawing drawing;
  drawing.source = source;
  drawing.width = 200;
  drawing.height = 400;
  SketchStroke trunk;
  trunk.points = {{100, 380}, {100, 200}};
  SketchStroke branch;
  branch.points = {{100, 200}, {140, 120}};
  SketchStroke crown;
  crown.role = StrokeRole::kCrown;
  crown.closed = true;
  for (int k = 0; k < 48; ++k) {
    const double a = 2 * M_PI * k / 48;
    crown.points.emplace_back(100 + 80 * std::cos(a), 130 + 80 * std::sin(a));
  }
  drawing.strokes = {trunk, branch, crown};
  return drawing;
}

// The largest matte value in the 3 x 3 pixels about (x, y).
float Peak(const FloatImage& matte, int x, int y) {
  float peak = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) peak = std::max(peak, matte.at(x + dx, y + dy));
  }
  return peak;
}

TEST(SketchViewsTest, ADrawingBecomesAViewWithAnOrthographicCameraAndADepthPrior) {
  SketchViewOptions options;
  options.image_size = 200;  // half the canvas: 100 x 200 pixels
  options.tree_height = 5.0;
  const SketchViews views = MakeSketchViews({Lollipop()}, options);
  ASSERT_EQ(views.views.size(), 2u);
  ASSERT_EQ(views.cameras.NumViews(), 2);
  EXPECT_EQ(views.views[0].name, "front.png");
  EXPECT_EQ(views.views[1].name, "front.depth.png");
  EXPECT_FALSE(views.views[0].is_virtual);
  EXPECT_TRUE(views.views[1].is_virtual);
  const FloatImage& matte = views.views[0].matte;
  ASSERT_EQ(matte.width(), 100);
  ASSERT_EQ(matte.height(), 200);

  // The base is the world origin, the top of the crown (50 px up from the
  // crown's top, 380 - 50 = 330 canvas px above the base) is 5 m up.
  Eigen::Vector2d pixel;
  ASSERT_TRUE(views.cameras.Project(0, Eigen::Vector3d::Zero(), &pixel));
  EXPECT_NEAR(pixel.x(), 50.0, 1e-9);
  EXPECT_NEAR(pixel.y(), 190.0, 1e-9);
  ASSERT_TRUE(views.cameras.Project(0, Eigen::Vector3d(0, 0, 5), &pixel));
  EXPECT_NEAR(pixel.y(), 25.0, 1e-9);
  // World +x is to the right in the front view; +y in the side view.
  ASSERT_TRUE(views.cameras.Project(0, Eigen::Vector3d(1, 0, 0), &pixel));
  EXPECT_GT(pixel.x(), 50.0);
  ASSERT_TRUE(views.cameras.Project(1, Eigen::Vector3d(0, 1, 0), &pixel));
  EXPECT_GT(pixel.x(), 50.0);
  ASSERT_TRUE(views.cameras.Project(1, Eigen::Vector3d(1, 0, 0), &pixel));
  EXPECT_NEAR(pixel.x(), 50.0, 1e-9) << "the side view looks along -x";
  // The drawn camera at the canvas size puts the base where it was drawn.
  ASSERT_TRUE(views.drawing_cameras.Project(0, Eigen::Vector3d::Zero(), &pixel));
  EXPECT_NEAR((pixel - Eigen::Vector2d(100, 380)).norm(), 0.0, 1e-9);
  EXPECT_EQ(views.drawing_cameras.CameraOf(0).width(), 200);

  // The matte: the crown filled at crown_opacity, the lines opaque, the
  // background empty.
  EXPECT_NEAR(matte.at(30, 65), options.crown_opacity, 1e-6);  // inside the crown
  EXPECT_GT(Peak(matte, 50, 150), 0.4f);                       // on the trunk
  EXPECT_EQ(Peak(matte, 10, 150), 0.0f);                       // beside it
  EXPECT_GT(Peak(matte, 10, 65), 0.4f);                        // on the crown's outline
  // The depth view is the front's silhouette made symmetric about the trunk.
  const FloatImage& side = views.views[1].matte;
  for (int y = 0; y < side.height(); y += 7) {
    for (int x = 0; x < 50; x += 3) EXPECT_EQ(side.at(x, y), side.at(99 - x, y)) << x << "," << y;
  }
  EXPECT_NEAR(side.at(25, 65), options.crown_opacity, 1e-6);

  // The branch strokes, in the view's pixels, rooted at the base.
  const StrokeSet& strokes = views.views[0].strokes;
  ASSERT_EQ(strokes.strokes.size(), 2u);
  EXPECT_EQ(strokes.width, 100);
  ASSERT_TRUE(strokes.root.has_value());
  EXPECT_NEAR((*strokes.root - Eigen::Vector2d(50, 190)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((strokes.strokes[1].points[1] - Eigen::Vector2d(70, 60)).norm(), 0.0, 1e-9);
  // The depth view: the trunk up the axis to the trunk's top, then the
  // major branches of the symmetric crown (a disc: one, straight up).
  const StrokeSet& side_strokes = views.views[1].strokes;
  ASSERT_EQ(side_strokes.strokes.size(), 2u);
  EXPECT_NEAR((side_strokes.strokes[0].points[0] - Eigen::Vector2d(50, 190)).norm(), 0, 1e-9);
  EXPECT_NEAR((side_strokes.strokes[0].points[1] - Eigen::Vector2d(50, 100)).norm(), 0, 1e-9);
  const Eigen::Vector2d tip = side_strokes.strokes[1].points.back();
  EXPECT_LT((tip - Eigen::Vector2d(50, 65)).norm(), 40.0) << "in the crown";
  EXPECT_LT(tip.y(), 100 - 0.5 * (100 - 25)) << "most of the way up to the crown's top";
}

// A cloud of three round bumps over a trunk ending at (100, 150): one major
// branch towards each bump, inside the crown.
// A root marked a little below the trunk's foot (the ground under it) is
// lifted onto the strokes' lowest line: the base is where the trunk ends, so
// the density, made from the strokes, holds it. Marked on the trunk, or far
// below, it stays where it was marked.
TEST(SketchViewsTest, ARootMarkedJustBelowTheTrunkIsLiftedOntoIt) {
  SketchViewOptions options;
  options.image_size = 200;
  const auto base_pixel = [&](const Eigen::Vector2d& root) {
    SketchDrawing drawing = Lollipop();
    drawing.height = 500;  // room below the trunk
    drawing.root = root;
    const SketchViews views = MakeSketchViews({drawing}, options);
    Eigen::Vector2d pixel;
    EXPECT_TRUE(views.drawing_cameras.Project(0, Eigen::Vector3d::Zero(), &pixel));
    return pixel;
  };
  // The drawing spans 50-380 px (crown top to trunk foot): up to 33 px below
  // the foot is lifted.
  EXPECT_NEAR((base_pixel({100, 390}) - Eigen::Vector2d(100, 380)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((base_pixel({103, 385}) - Eigen::Vector2d(103, 380)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((base_pixel({100, 370}) - Eigen::Vector2d(100, 370)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((base_pixel({100, 440}) - Eigen::Vector2d(100, 440)).norm(), 0.0, 1e-9);
}

TEST(SketchViewsTest, MajorBranchesGrowIntoTheCrownsBumps) {
  FloatImage matte(200, 200, 1);
  const Eigen::Vector2d bumps[] = {{60, 90}, {100, 50}, {140, 90}};
  for (int y = 0; y < 200; ++y) {
    for (int x = 0; x < 200; ++x) {
      for (const Eigen::Vector2d& c : bumps) {
        if ((Eigen::Vector2d(x + 0.5, y + 0.5) - c).norm() < 34) matte.at(x, y) = 0.6f;
      }
    }
  }
  const std::vector<Stroke> branches = InferMajorBranches(matte, SketchViewOptions(), {100, 150});
  ASSERT_EQ(branches.size(), 3u);
  for (const Stroke& branch : branches) {
    EXPECT_NEAR((branch.points.front() - Eigen::Vector2d(100, 150)).norm(), 0.0, 1e-9);
    const Eigen::Vector2d tip = branch.points.back();
    double nearest = 1e9;
    for (const Eigen::Vector2d& c : bumps) nearest = std::min(nearest, (tip - c).norm());
    EXPECT_LT(nearest, 34.0) << "the tip " << tip.transpose() << " lies in a bump";
  }
  EXPECT_TRUE(InferMajorBranches(FloatImage(50, 50, 1), SketchViewOptions(), {25, 40}).empty());
}

TEST(SketchViewsTest, TwoDrawingsAreFrontAndSideWithoutAPrior) {
  SketchViewOptions options;
  options.image_size = 128;
  const SketchViews views = MakeSketchViews({Lollipop("front.svg"), Lollipop("side.svg")}, options);
  ASSERT_EQ(views.views.size(), 2u);
  EXPECT_FALSE(views.views[1].is_virtual);
  EXPECT_EQ(views.views[1].strokes.strokes.size(), 2u);
  const Eigen::Vector3d up(0, 0, options.tree_height);
  Eigen::Vector2d front, side;
  ASSERT_TRUE(views.cameras.Project(0, up, &front));
  ASSERT_TRUE(views.cameras.Project(1, up, &side));
  EXPECT_NEAR((front - side).norm(), 0.0, 1e-9) << "the same tree height in both";
}

TEST(SketchViewsTest, DeterministicAndBadDrawingsAreNamed) {
  const SketchViews a = MakeSketchViews({Lollipop()}, SketchViewOptions());
  const SketchViews b = MakeSketchViews({Lollipop()}, SketchViewOptions());
  EXPECT_EQ(a.views[0].matte.values(), b.views[0].matte.values());

  SketchDrawing flat = Lollipop("flat.svg");
  flat.strokes = {flat.strokes[0]};
  flat.strokes[0].points = {{20, 300}, {180, 300}};
  try {
    MakeSketchViews({flat}, SketchViewOptions());
    FAIL() << "a drawing without height";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("flat.svg"), std::string::npos) << error.what();
  }
  EXPECT_THROW(MakeSketchViews({Lollipop("a.svg"), Lollipop("a.png")}, SketchViewOptions()),
               InputError)
      << "both would be the view a.png";
  EXPECT_THROW(MakeSketchViews(std::vector<SketchDrawing>(5, Lollipop()), SketchViewOptions()),
               InputError);
  SketchViewOptions bad;
  bad.crown_opacity = 1.0;
  EXPECT_THROW(MakeSketchViews({Lollipop()}, bad), InputError);
}

}  // namespace
}  // namespace sylva
