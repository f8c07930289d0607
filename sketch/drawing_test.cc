#include "sketch/drawing.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/util/check.h"

namespace sylva {
namespace {

SketchDrawing TwoStrokes() {
  SketchDrawing drawing;
  drawing.source = "tree.svg";
  drawing.width = 200;
  drawing.height = 300;
  SketchStroke trunk;
  trunk.points = {{100, 290}, {100, 150}};
  SketchStroke crown;
  crown.role = StrokeRole::kCrown;
  crown.closed = true;
  crown.points = {{40, 150}, {100, 20}, {160, 150}};
  drawing.strokes = {trunk, crown};
  return drawing;
}

TEST(SketchDrawingTest, RolesByName) {
  for (StrokeRole role :
       {StrokeRole::kBranch, StrokeRole::kCrown, StrokeRole::kConstruction, StrokeRole::kOrgan}) {
    EXPECT_EQ(StrokeRoleFromName(StrokeRoleName(role)), role);
  }
  EXPECT_EQ(StrokeRoleFromName("Crown"), StrokeRole::kCrown);
  EXPECT_FALSE(StrokeRoleFromName("leaf").has_value());
}

TEST(SketchDrawingTest, CountsRolesAndAcceptsAGoodDrawing) {
  const SketchDrawing drawing = TwoStrokes();
  EXPECT_NO_THROW(drawing.Check());
  EXPECT_EQ(drawing.CountRole(StrokeRole::kBranch), 1);
  EXPECT_EQ(drawing.CountRole(StrokeRole::kCrown), 1);
  EXPECT_EQ(drawing.CountRole(StrokeRole::kOrgan), 0);
}

TEST(SketchDrawingTest, BadDrawingsAreNamed) {
  const auto message = [](const SketchDrawing& drawing) {
    try {
      drawing.Check();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SketchDrawing empty = TwoStrokes();
  empty.strokes.clear();
  EXPECT_NE(message(empty).find("tree.svg"), std::string::npos);
  EXPECT_NE(message(empty).find("no strokes"), std::string::npos);
  SketchDrawing short_outline = TwoStrokes();
  short_outline.strokes[1].points.pop_back();
  EXPECT_NE(message(short_outline).find("needs at least 3"), std::string::npos);
  SketchDrawing far = TwoStrokes();
  far.strokes[0].points[0] = {1e6, 0};
  EXPECT_NE(message(far).find("far outside"), std::string::npos);
  SketchDrawing nan = TwoStrokes();
  nan.strokes[0].points[1].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(nan).find("far outside"), std::string::npos);
  SketchDrawing no_canvas = TwoStrokes();
  no_canvas.width = 0;
  EXPECT_NE(message(no_canvas).find("canvas size"), std::string::npos);
}

}  // namespace
}  // namespace sylva
