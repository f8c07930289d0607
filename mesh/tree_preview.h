// Preview pictures of a tree for reports: the bark mesh and its leaves, lit
// by a sun (directional light, hard shadows) and a sky (ambient that is
// brighter on faces turned up), seen from several azimuths by orthographic
// cameras framed exactly around the tree.
//
// Leaves are either Embree instances of one leaf geometry (the
// LeafInstances' shape) under each leaf's transform, so 10^5 leaves cost one
// small leaf mesh plus 10^5 transforms instead of 10^5 copies, or, when the
// shape is untextured, triangles of the scene's mesh (the same picture,
// traced about 1.5x faster for a larger BVH: ChoosePreviewLeafGeometry
// picks). A textured leaf shape (LeafShapeFromImage) is always instanced,
// alpha-tested against its texture (alpha >= 0.5 keeps the hit, like glTF's
// MASK mode) and coloured by it. Leaves are double-sided and let a fraction
// of the sun through when lit from behind.
//
// World frame: +Z up (sylva's world frame, also the ITSMe QSM tables').
// Cameras follow COLMAP (x right, y down, z forward). Every pixel is sampled
// by S x S stratified rays; rows are traced in parallel (TBB) and every
// pixel depends only on its own rays, so renders are deterministic.
// Embree stays an implementation detail of tree_preview.cc.
#ifndef SYLVA_MESH_TREE_PREVIEW_H_
#define SYLVA_MESH_TREE_PREVIEW_H_

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/box.h"
#include "core/geometry/rigid3.h"
#include "core/types/camera.h"
#include "core/types/float_image.h"
#include "core/types/triangle_mesh.h"
#include "mesh/leaves.h"

namespace sylva {

struct TreePreviewOptions {
  // Picture size in pixels.
  int width = 640;
  int height = 640;
  // Rays per pixel along each image axis (S x S rays per pixel), >= 1.
  int samples_per_axis = 3;
  // Views around the tree, in degrees. Azimuth 0 looks along +Y (the camera
  // on the -Y side, +X to the right); larger azimuths move the camera
  // counter-clockwise around the tree seen from above (90: camera on +X).
  std::vector<double> azimuths_deg = {0.0, 90.0, 180.0, 270.0};
  // Angle of the views above the horizon, degrees, in [-89, 89].
  double elevation_deg = 15.0;
  // Adds a view straight down (+Y up in the picture) after the azimuths.
  bool top_view = false;
  // Empty border around the tree's bounding box, fraction of the picture's
  // smaller side on each side, in [0, 0.4).
  double margin = 0.04;
  // Direction towards the sun, world frame (need not be unit, non-zero).
  // Default: high, from the front right of the azimuth-0 view.
  Eigen::Vector3d sun_direction = Eigen::Vector3d(0.45, -0.55, 0.7);
  // Sun and sky radiance multipliers (>= 0): a face lit head-on by the sun
  // and facing straight up gets (sun + sky) x its colour.
  double sun_intensity = 0.85;
  double sky_intensity = 0.35;
  // Shadow rays towards the sun (hard shadows); false = no shadows.
  bool shadows = true;
  // Fraction of the sun a leaf lit from behind passes to its other face, [0, 1].
  double leaf_translucency = 0.35;
  // Interpolated vertex normals on the mesh (smooth bark); false = flat faces.
  bool smooth_normals = true;
  // true: composited over white, alpha 1; false: straight-alpha RGBA over
  // nothing (alpha = coverage).
  bool white_background = true;
  // Encode colours with the sRGB transfer curve (for PNG pictures); false =
  // linear values. Material colours are linear RGB.
  bool srgb = true;

  // Throws InputError("TreePreview.<field>", ...) naming the violated constraint.
  void Check() const;
};

// A camera and its pose for one preview picture. Rays start on the camera's
// image plane (an orthographic camera's) or at its centre (pinhole), so
// geometry in front of that plane is not seen.
struct PreviewView {
  std::string name;  // "azimuth_90", "top", "close_up"
  Camera camera;
  Rigid3d cam_from_world;
};

// The views of options (azimuths, then top) framing `bounds` (world frame,
// non-empty): orthographic cameras of width x height pixels whose image
// holds the box's projection centred, with `margin` left on the tighter
// side; each camera's image plane lies outside the box.
std::vector<PreviewView> FramedPreviewViews(const Box3d& bounds, const TreePreviewOptions& options);

// An orthographic close-up: the sphere (center, radius > 0, world units)
// fills the picture's smaller side minus the margins, seen from
// (azimuth_deg, elevation_deg) as above; the image plane passes `radius` in
// front of `center`, so nearer geometry is clipped away.
PreviewView CloseUpView(const Eigen::Vector3d& center, double radius, double azimuth_deg,
                        double elevation_deg, const TreePreviewOptions& options);

// How the renderer holds the leaves.
enum class PreviewLeafGeometry {
  kInstances,  // one leaf geometry, one Embree instance per leaf
  kTriangles,  // every leaf's triangles in the scene's mesh (untextured shapes only)
};

// Triangles when the leaf shape is untextured and the baked triangles are
// few beside the camera rays to trace (`num_rays`): building a BVH over
// baked leaves costs about as much per triangle as the faster tracing saves
// on 5 rays (sylva_preview_benchmark); else instances.
PreviewLeafGeometry ChoosePreviewLeafGeometry(const LeafInstances* leaves, double num_rays);

// Scene figures, for benchmarks and reports.
struct TreePreviewStats {
  int mesh_triangles = 0;  // of the mesh given (baked leaves not counted)
  int leaf_instances = 0;
  int leaf_triangles = 0;  // of the one leaf geometry
  bool leaves_as_triangles = false;
  double build_seconds = 0.0;
};

class TreePreviewRenderer {
 public:
  // Builds the scene once: `mesh` (bark, or anything with materials; may
  // hold baked leaves) and `leaves` (may be null or empty) held as
  // `leaf_geometry` says (kTriangles needs an untextured shape). Copies what
  // it needs. Throws Error if the mesh or leaf shape fails Check().
  TreePreviewRenderer(const TriangleMesh& mesh, const LeafInstances* leaves,
                      PreviewLeafGeometry leaf_geometry = PreviewLeafGeometry::kInstances);
  ~TreePreviewRenderer();
  TreePreviewRenderer(TreePreviewRenderer&&) noexcept;
  TreePreviewRenderer& operator=(TreePreviewRenderer&&) noexcept;
  TreePreviewRenderer(const TreePreviewRenderer&) = delete;
  TreePreviewRenderer& operator=(const TreePreviewRenderer&) = delete;

  // Bounds of the mesh and every leaf (empty box for an empty scene).
  Box3d Bounds() const;
  const TreePreviewStats& Stats() const;

  // FramedPreviewViews' views, with each camera framing the projections of
  // every vertex (of the mesh and of every leaf) instead of the bounding
  // box's corners: the silhouette itself fills the picture up to the margin
  // on its tighter side. Throws InputError for bad options or an empty scene.
  std::vector<PreviewView> FramedViews(const TreePreviewOptions& options) const;

  // An RGBA picture of view.camera's size (see TreePreviewOptions for the
  // background and encoding). Const and thread-safe.
  FloatImage Render(const PreviewView& view, const TreePreviewOptions& options) const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// One picture per TreePreviewRenderer::FramedViews view, the leaves held as
// ChoosePreviewLeafGeometry says. Throws InputError for bad options, and if
// the scene is empty.
std::vector<FloatImage> RenderTreePreviews(const TriangleMesh& mesh, const LeafInstances* leaves,
                                           const TreePreviewOptions& options);

// A close-up picture (CloseUpView) of the scene.
FloatImage RenderCloseUp(const TriangleMesh& mesh, const LeafInstances* leaves,
                         const Eigen::Vector3d& center, double radius, double azimuth_deg,
                         double elevation_deg, const TreePreviewOptions& options);

}  // namespace sylva

#endif  // SYLVA_MESH_TREE_PREVIEW_H_
