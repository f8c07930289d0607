#include "mesh/tree_preview.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"
#include "core/util/random.h"
#include "datasets/synthetic/synthetic_tree.h"

namespace sylva {
namespace {

const Eigen::Vector3f kGrey(0.5f, 0.5f, 0.5f);

// A closed UV sphere (outward counter-clockwise triangles).
TriangleMesh Sphere(const Eigen::Vector3f& center, float radius, int rings, int segments) {
  TriangleMesh mesh;
  const int material = mesh.AddMaterial({"ball", kGrey, false});
  const int north = mesh.AddVertex(center + radius * Eigen::Vector3f::UnitZ());
  for (int r = 1; r < rings; ++r) {
    const double polar = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2.0 * M_PI * s / segments;
      mesh.AddVertex(center + radius * Eigen::Vector3d(std::sin(polar) * std::cos(azimuth),
                                                       std::sin(polar) * std::sin(azimuth),
                                                       std::cos(polar))
                                           .cast<float>());
    }
  }
  const int south = mesh.AddVertex(center - radius * Eigen::Vector3f::UnitZ());
  auto at = [&](int ring, int s) { return 1 + (ring - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.AddTriangle(north, at(1, s), at(1, s + 1), material);
    mesh.AddTriangle(south, at(rings - 1, s + 1), at(rings - 1, s), material);
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.AddTriangle(at(r, s), at(r + 1, s), at(r + 1, s + 1), material);
      mesh.AddTriangle(at(r, s), at(r + 1, s + 1), at(r, s + 1), material);
    }
  }
  return mesh;
}

// A closed axis-aligned box.
TriangleMesh Box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                 const Eigen::Vector3f& color) {
  TriangleMesh mesh;
  const int material = mesh.AddMaterial({"box", color, false});
  for (int k = 0; k < 8; ++k) {
    mesh.AddVertex(
        Eigen::Vector3f(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z()));
  }
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    mesh.AddTriangle(f[0], f[1], f[2], material);
    mesh.AddTriangle(f[0], f[2], f[3], material);
  }
  return mesh;
}

TreePreviewOptions LinearTransparent(int size) {
  TreePreviewOptions options;
  options.width = options.height = size;
  options.white_background = false;
  options.srgb = false;
  return options;
}

double SumChannel(const FloatImage& image, int channel) {
  double sum = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image.at(x, y, channel);
  return sum;
}

float Rand(RandomEngine& random) { return static_cast<float>(random.Uniform(-1, 1)); }

// Random leaves of the ovate shape in a ball of radius 1 around (0, 0, 2).
LeafInstances RandomLeaves(int count) {
  LeafInstances leaves;
  leaves.shape = BuiltinLeafShape("ovate", 0.6);
  leaves.material = {"leaves", Eigen::Vector3f(0.2f, 0.45f, 0.12f), true};
  RandomEngine random(7);
  for (int k = 0; k < count; ++k) {
    LeafInstance leaf;
    Eigen::Vector3f offset;
    do {
      offset = Eigen::Vector3f(Rand(random), Rand(random), Rand(random));
    } while (offset.norm() > 1.0f);
    leaf.translation = Eigen::Vector3f(0, 0, 2) + offset;
    leaf.rotation =
        Eigen::Quaternionf(Rand(random), Rand(random), Rand(random), Rand(random)).normalized();
    leaf.scale = 0.15f;
    leaves.instances.push_back(leaf);
  }
  return leaves;
}

TEST(TreePreviewTest, SphereSilhouetteHasTheProjectedArea) {
  const float radius = 0.8f;
  const TriangleMesh sphere = Sphere(Eigen::Vector3f(1, 2, 3), radius, 64, 128);
  const TreePreviewOptions options = LinearTransparent(200);
  const TreePreviewRenderer renderer(sphere, nullptr);
  const PreviewView view = CloseUpView(Eigen::Vector3d(1, 2, 3), 1.0, 30.0, 20.0, options);
  // The close-up's image plane lies 1.0 in front of the centre: the whole
  // sphere is behind it.
  const FloatImage picture = renderer.Render(view, options);
  const double pixel_area = 1.0 / std::pow(view.camera.FocalLengthX(), 2);
  const double area = SumChannel(picture, 3) * pixel_area;
  // The inscribed polygonal sphere's outline is a little smaller than the disc.
  EXPECT_NEAR(area / (M_PI * radius * radius), 1.0, 0.01);
  // Centred: the silhouette's centroid is the image centre.
  double cx = 0, cy = 0;
  for (int y = 0; y < picture.height(); ++y) {
    for (int x = 0; x < picture.width(); ++x) {
      cx += (x + 0.5) * picture.at(x, y, 3);
      cy += (y + 0.5) * picture.at(x, y, 3);
    }
  }
  EXPECT_NEAR(cx / SumChannel(picture, 3), 100.0, 0.2);
  EXPECT_NEAR(cy / SumChannel(picture, 3), 100.0, 0.2);
}

TEST(TreePreviewTest, FramingFitsTheBoxTightlyInsideTheMargin) {
  const TriangleMesh box = Box(Eigen::Vector3f(-1, -0.5, 0), Eigen::Vector3f(1, 0.5, 3), kGrey);
  TreePreviewOptions options = LinearTransparent(160);
  options.samples_per_axis = 2;
  options.top_view = true;
  options.margin = 0.05;
  const TreePreviewRenderer renderer(box, nullptr);
  const std::vector<PreviewView> views = FramedPreviewViews(renderer.Bounds(), options);
  ASSERT_EQ(views.size(), 5u);
  EXPECT_EQ(views[1].name, "azimuth_90");
  EXPECT_EQ(views[4].name, "top");
  for (const PreviewView& view : views) {
    const FloatImage picture = renderer.Render(view, options);
    // A box's silhouette is the hull of its projected corners: it spans the
    // picture minus the margins (8 px) along one axis, and stays inside both.
    int x0 = 1000, x1 = -1, y0 = 1000, y1 = -1;
    for (int y = 0; y < picture.height(); ++y) {
      for (int x = 0; x < picture.width(); ++x) {
        if (picture.at(x, y, 3) <= 0) continue;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
    SCOPED_TRACE(view.name);
    EXPECT_GE(std::min(x0, y0), 7);
    EXPECT_LE(std::max(x1, y1), 152);
    EXPECT_GE(std::max(x1 - x0, y1 - y0) + 1, 143);
    EXPECT_NEAR(0.5 * (x0 + x1 + 1), 80.0, 1.0);
    EXPECT_NEAR(0.5 * (y0 + y1 + 1), 80.0, 1.0);
  }
  // Azimuth 0 looks along +Y with +X to the right and +Z up.
  const Eigen::Vector2d right =
      views[0].camera.ImgFromCam(views[0].cam_from_world * Eigen::Vector3d(1, 0, 1.5));
  const Eigen::Vector2d top =
      views[0].camera.ImgFromCam(views[0].cam_from_world * Eigen::Vector3d(0, 0, 3));
  EXPECT_GT(right.x(), 80.0 + 10.0);
  EXPECT_LT(top.y(), 80.0 - 10.0);
}

TEST(TreePreviewTest, ShadowFallsWhereTheSunPredicts) {
  // A grey floor z = 0 and a box floating at z in [1, 1.5] over its middle;
  // sun at 45 degrees from +X: the box's shadow covers x in [-1.75, -0.75].
  TriangleMesh scene = Box(Eigen::Vector3f(-3, -3, -0.1f), Eigen::Vector3f(3, 3, 0), kGrey);
  scene.Append(Box(Eigen::Vector3f(-0.25f, -0.25f, 1), Eigen::Vector3f(0.25f, 0.25f, 1.5f), kGrey));
  TreePreviewOptions options = LinearTransparent(120);
  options.samples_per_axis = 1;
  options.azimuths_deg.clear();
  options.top_view = true;
  options.sun_direction = Eigen::Vector3d(1, 0, 1);
  options.smooth_normals = false;  // the floor's corners would tilt its normals
  const TreePreviewRenderer renderer(scene, nullptr);
  const PreviewView view = FramedPreviewViews(renderer.Bounds(), options)[0];
  const FloatImage picture = renderer.Render(view, options);
  auto value_at = [&](double x, double y) {
    const Eigen::Vector2d p =
        view.camera.ImgFromCam(view.cam_from_world * Eigen::Vector3d(x, y, 0));
    return picture.at(static_cast<int>(p.x()), static_cast<int>(p.y()), 1);
  };
  const double sky = options.sky_intensity * 0.5;  // n = +Z: full sky
  const double lit = 0.5 * (options.sun_intensity * std::sqrt(0.5) + options.sky_intensity);
  for (double x : {-1.6, -1.25, -0.9}) {
    for (double y : {-0.15, 0.0, 0.15}) EXPECT_NEAR(value_at(x, y), sky, 1e-4) << x << " " << y;
  }
  for (double x : {-2.2, 0.6, 1.25, 2.0}) EXPECT_NEAR(value_at(x, 0.0), lit, 1e-4) << x;
  EXPECT_NEAR(value_at(-1.25, 0.6), lit, 1e-4);
  // Without shadow rays the floor is lit everywhere.
  options.shadows = false;
  const FloatImage unshadowed = renderer.Render(view, options);
  const Eigen::Vector2d p =
      view.camera.ImgFromCam(view.cam_from_world * Eigen::Vector3d(-1.25, 0, 0));
  EXPECT_NEAR(unshadowed.at(static_cast<int>(p.x()), static_cast<int>(p.y()), 1), lit, 1e-4);
}

TEST(TreePreviewTest, InstancedLeavesLookLikeBakedLeavesAndRendersRepeat) {
  const TriangleMesh trunk = Box(Eigen::Vector3f(-0.1f, -0.1f, 0), Eigen::Vector3f(0.1f, 0.1f, 2),
                                 Eigen::Vector3f(0.35f, 0.25f, 0.18f));
  const LeafInstances leaves = RandomLeaves(400);
  TriangleMesh baked = trunk;
  baked.Append(leaves.Bake());
  TreePreviewOptions options;
  options.width = options.height = 96;
  options.samples_per_axis = 2;
  options.azimuths_deg = {0.0, 135.0};
  const TreePreviewRenderer instanced_renderer(trunk, &leaves);
  const TreePreviewRenderer baked_renderer(baked, nullptr);
  EXPECT_EQ(instanced_renderer.Stats().leaf_instances, 400);
  EXPECT_EQ(instanced_renderer.Stats().mesh_triangles, 12);
  EXPECT_EQ(baked_renderer.Stats().mesh_triangles,
            12 + 400 * instanced_renderer.Stats().leaf_triangles);
  EXPECT_LT((instanced_renderer.Bounds().min() - baked_renderer.Bounds().min()).norm(), 1e-5);
  EXPECT_LT((instanced_renderer.Bounds().max() - baked_renderer.Bounds().max()).norm(), 1e-5);
  for (const PreviewView& view : FramedPreviewViews(instanced_renderer.Bounds(), options)) {
    const FloatImage instanced = instanced_renderer.Render(view, options);
    const FloatImage baked_picture = baked_renderer.Render(view, options);
    double difference = 0, leafy = 0;
    for (int y = 0; y < instanced.height(); ++y) {
      for (int x = 0; x < instanced.width(); ++x) {
        for (int c = 0; c < 4; ++c) {
          difference += std::abs(instanced.at(x, y, c) - baked_picture.at(x, y, c));
        }
        // Leaf green: more green than red.
        leafy += instanced.at(x, y, 1) > instanced.at(x, y, 0) + 0.05f ? 1 : 0;
      }
    }
    SCOPED_TRACE(view.name);
    EXPECT_LT(difference / (4.0 * instanced.width() * instanced.height()), 2e-3);
    EXPECT_GT(leafy, 0.05 * instanced.width() * instanced.height());
    // Deterministic: the same picture again, value for value.
    const FloatImage again = instanced_renderer.Render(view, options);
    EXPECT_TRUE(again.values() == instanced.values());
  }
}

TEST(TreePreviewTest, LeavesHeldAsTrianglesDrawTheSamePicture) {
  const TriangleMesh trunk = Box(Eigen::Vector3f(-0.1f, -0.1f, 0), Eigen::Vector3f(0.1f, 0.1f, 2),
                                 Eigen::Vector3f(0.35f, 0.25f, 0.18f));
  const LeafInstances leaves = RandomLeaves(300);
  TreePreviewOptions options;
  options.width = options.height = 80;
  options.samples_per_axis = 2;
  options.azimuths_deg = {30.0, 200.0};
  const TreePreviewRenderer instanced(trunk, &leaves, PreviewLeafGeometry::kInstances);
  const TreePreviewRenderer triangles(trunk, &leaves, PreviewLeafGeometry::kTriangles);
  EXPECT_FALSE(instanced.Stats().leaves_as_triangles);
  EXPECT_TRUE(triangles.Stats().leaves_as_triangles);
  EXPECT_EQ(triangles.Stats().mesh_triangles, 12);  // the leaves are not the mesh's
  EXPECT_EQ(triangles.Stats().leaf_instances, 300);
  const std::vector<PreviewView> views = instanced.FramedViews(options);
  const std::vector<PreviewView> same_views = triangles.FramedViews(options);
  ASSERT_EQ(views.size(), same_views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    SCOPED_TRACE(views[v].name);
    // The framing sees the same vertices either way.
    for (size_t k = 0; k < views[v].camera.params().size(); ++k) {
      EXPECT_NEAR(views[v].camera.params()[k], same_views[v].camera.params()[k], 1e-6);
    }
    const FloatImage a = instanced.Render(views[v], options);
    const FloatImage b = triangles.Render(views[v], options);
    double difference = 0;
    for (size_t i = 0; i < a.values().size(); ++i)
      difference += std::abs(a.values()[i] - b.values()[i]);
    // Instances round the leaf transform per ray: a few edge samples move.
    EXPECT_LT(difference / a.values().size(), 2e-3);
    EXPECT_GT(SumChannel(b, 1), SumChannel(b, 0));  // leaf green shows
  }
  // A textured shape is alpha-tested: it is never baked.
  LeafInstances textured = leaves;
  FloatImage rgba(8, 8, 4);
  rgba.values().assign(rgba.values().size(), 1.0f);
  textured.shape = LeafShapeFromImage(rgba, "square");
  EXPECT_THROW(TreePreviewRenderer(trunk, &textured, PreviewLeafGeometry::kTriangles), Error);
}

TEST(TreePreviewTest, LeavesAreBakedOnlyWhenFewBesideTheRays) {
  const LeafInstances leaves = RandomLeaves(1000);  // ovate: 1000 x its triangles
  const double triangles = 1000.0 * leaves.shape.triangles.size();
  EXPECT_EQ(ChoosePreviewLeafGeometry(&leaves, 5.0 * triangles), PreviewLeafGeometry::kTriangles);
  EXPECT_EQ(ChoosePreviewLeafGeometry(&leaves, 4.0 * triangles), PreviewLeafGeometry::kInstances);
  EXPECT_EQ(ChoosePreviewLeafGeometry(nullptr, 1e9), PreviewLeafGeometry::kInstances);
  LeafInstances textured = leaves;
  FloatImage rgba(8, 8, 4);
  rgba.values().assign(rgba.values().size(), 1.0f);
  textured.shape = LeafShapeFromImage(rgba, "square");
  EXPECT_EQ(ChoosePreviewLeafGeometry(&textured, 1e12), PreviewLeafGeometry::kInstances);
}

TEST(TreePreviewTest, ImageLeavesAreAlphaTestedAndColouredByTheirTexture) {
  // A red disc on a transparent square: the leaf quad spans the disc's box
  // and is kept where alpha >= 0.5, so it covers pi / 4 of the quad.
  FloatImage rgba(64, 64, 4);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool inside = std::hypot(x + 0.5 - 32, y + 0.5 - 32) < 32;
      rgba.at(x, y, 0) = 1.0f;
      rgba.at(x, y, 3) = inside ? 1.0f : 0.0f;
    }
  }
  LeafInstances leaves;
  leaves.shape = LeafShapeFromImage(rgba, "disc");
  leaves.material = {"leaves", Eigen::Vector3f(0, 1, 0), true};
  LeafInstance leaf;  // upper face +Z, one unit long
  leaf.translation = Eigen::Vector3f(-0.5f, 0, 0);
  leaves.instances.push_back(leaf);
  TreePreviewOptions options = LinearTransparent(100);
  options.sun_intensity = 0.0;
  options.sky_intensity = 1.0;
  const TreePreviewRenderer renderer(TriangleMesh(), &leaves);
  options.azimuths_deg.clear();
  options.top_view = true;
  options.margin = 0.0;
  const PreviewView view = FramedPreviewViews(renderer.Bounds(), options)[0];
  const FloatImage picture = renderer.Render(view, options);
  EXPECT_NEAR(SumChannel(picture, 3) / (100.0 * 100.0), M_PI / 4, 0.01);
  // Texture red (sRGB 1 = linear 1), not the material's green.
  EXPECT_NEAR(picture.at(50, 50, 0), 1.0, 1e-5);
  EXPECT_NEAR(picture.at(50, 50, 1), 0.0, 1e-5);
}

TEST(TreePreviewTest, SyntheticTreeStaysInsideEveryView) {
  SyntheticTreeOptions tree_options;
  tree_options.num_children = {6, 3, 0};
  tree_options.leaves_per_cluster = 16;
  const SyntheticTree tree = GenerateSyntheticTree(tree_options, 3);
  TreePreviewOptions options = LinearTransparent(96);
  options.samples_per_axis = 2;
  options.top_view = true;
  const std::vector<FloatImage> pictures = RenderTreePreviews(tree.mesh, nullptr, options);
  ASSERT_EQ(pictures.size(), 5u);
  for (const FloatImage& picture : pictures) {
    double border = 0;
    for (int k = 0; k < 96; ++k) {
      border +=
          picture.at(k, 0, 3) + picture.at(k, 95, 3) + picture.at(0, k, 3) + picture.at(95, k, 3);
    }
    EXPECT_EQ(border, 0.0);
    EXPECT_GT(SumChannel(picture, 3), 0.03 * 96 * 96);
    // Framed on the vertices, the silhouette reaches the margin (3.84 px) on
    // its tighter axis.
    int x0 = 96, x1 = -1, y0 = 96, y1 = -1;
    for (int y = 0; y < 96; ++y) {
      for (int x = 0; x < 96; ++x) {
        if (picture.at(x, y, 3) <= 0) continue;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
    EXPECT_GE(std::max(x1 - x0, y1 - y0) + 1, 96 - 2 * 3.84 - 2);
  }
}

TEST(TreePreviewTest, BadOptionsNameTheOption) {
  auto message_of = [](const TreePreviewOptions& options) {
    try {
      options.Check();
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::vector<std::pair<std::string, void (*)(TreePreviewOptions*)>> cases = {
      {"TreePreview.width", [](TreePreviewOptions* o) { o->width = 0; }},
      {"TreePreview.height", [](TreePreviewOptions* o) { o->height = 100000; }},
      {"TreePreview.samples_per_axis", [](TreePreviewOptions* o) { o->samples_per_axis = 0; }},
      {"TreePreview.elevation_deg", [](TreePreviewOptions* o) { o->elevation_deg = 95; }},
      {"TreePreview.margin", [](TreePreviewOptions* o) { o->margin = 0.5; }},
      {"TreePreview.azimuths_deg", [](TreePreviewOptions* o) { o->azimuths_deg.clear(); }},
      {"TreePreview.sun_direction", [](TreePreviewOptions* o) { o->sun_direction.setZero(); }},
      {"TreePreview.leaf_translucency", [](TreePreviewOptions* o) { o->leaf_translucency = 2; }},
  };
  for (const auto& [name, spoil] : cases) {
    TreePreviewOptions options;
    spoil(&options);
    EXPECT_NE(message_of(options).find(name), std::string::npos) << name;
  }
  EXPECT_THROW(RenderTreePreviews(TriangleMesh(), nullptr, TreePreviewOptions()), InputError);
  EXPECT_THROW(CloseUpView(Eigen::Vector3d::Zero(), 0.0, 0, 0, TreePreviewOptions()), InputError);
}

}  // namespace
}  // namespace sylva
