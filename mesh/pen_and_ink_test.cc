// Pen-and-ink drawings: outlines with hidden lines removed by ray casts,
// hatching on the dark side only, Inkscape layers in the SVG.
#include "mesh/pen_and_ink.h"

#include <gtest/gtest.h>

#include <string>

#include "core/util/check.h"

namespace sylva {
namespace {

// An axis-aligned box [lo, hi] as 12 outward triangles.
void AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int material,
            TriangleMesh* mesh) {
  const int base = mesh->NumVertices();
  for (int i = 0; i < 8; ++i) {
    mesh->AddVertex(
        Eigen::Vector3f(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()));
  }
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) mesh->AddTriangle(base + f[0], base + f[1], base + f[2], material);
}

TEST(PenAndInkTest, HiddenEdgesAreDroppedAndDarkFacesHatched) {
  TriangleMesh mesh;
  const int m = mesh.AddMaterial({"bark", Eigen::Vector3f(0.5f, 0.4f, 0.3f), false});
  // A small box in front of (at smaller y than) a large one: seen from the
  // front (looking along +y), the small box hides part of the large one's
  // front outline... and the large box's back edges are hidden by itself.
  AddBox(Eigen::Vector3f(-1, 0, -1), Eigen::Vector3f(1, 2, 1), m, &mesh);
  AddBox(Eigen::Vector3f(-0.3f, -1, -0.3f), Eigen::Vector3f(0.3f, -0.5f, 0.3f), m, &mesh);
  PenAndInkOptions options;
  options.image_size = 200;
  options.light_direction = Eigen::Vector3d(1, -1, 1);  // the front faces half lit
  const PenAndInkDrawing drawing =
      DrawPenAndInk(mesh, {}, {{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, -1, 1)}},
                    PenAndInkView::FromAngles(0, 0), options);
  EXPECT_GT(drawing.outline.size(), 0u);
  EXPECT_GT(drawing.hidden_outline_samples, 0);
  EXPECT_LT(drawing.hidden_outline_samples, drawing.outline_samples);
  // Front faces: normal -y, light (1, -1, 1)/sqrt(3): tone 1 - 0.577 = 0.42 <
  // 0.45, no hatching; seen faces all face -y, so none is hatched.
  EXPECT_EQ(drawing.hatching.size(), 0u);
  options.light_direction = Eigen::Vector3d(0, 1, 0);  // from behind: everything dark
  const PenAndInkDrawing dark =
      DrawPenAndInk(mesh, {}, {}, PenAndInkView::FromAngles(0, 0), options);
  EXPECT_GT(dark.hatching.size(), 20u);
  // Every hatching stroke lies over the boxes' silhouette (|x|, |z| <= 1).
  const std::string svg = PenAndInkSvg(drawing);
  for (const char* layer : {"inkscape:label=\"outline\"", "inkscape:label=\"hatching\"",
                            "inkscape:label=\"construction\"", "inkscape:groupmode=\"layer\""}) {
    EXPECT_NE(svg.find(layer), std::string::npos) << layer;
  }
  const FloatImage image = RasterizePenAndInk(dark);
  EXPECT_EQ(image.width(), dark.width);
  int inked = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) inked += image.at(x, y, 0) < 0.5f ? 1 : 0;
  }
  EXPECT_GT(inked, 200);
  EXPECT_LT(inked, image.width() * image.height() / 2);
}

TEST(PenAndInkTest, ViewsFromAngles) {
  const PenAndInkView front = PenAndInkView::FromAngles(0, 0);
  EXPECT_TRUE(front.view_direction.isApprox(Eigen::Vector3d::UnitY()));
  const PenAndInkView top = PenAndInkView::FromAngles(0, 90);
  EXPECT_NEAR(top.view_direction.z(), -1.0, 1e-12);
  PenAndInkOptions bad;
  bad.image_size = 10;
  EXPECT_THROW(bad.Check(), InputError);
}

}  // namespace
}  // namespace sylva
