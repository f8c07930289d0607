#include "reconstruct/density/visual_hull.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/convex_polytope.h"
#include "core/geometry/voxel_traversal.h"
#include "core/util/check.h"
#include "reconstruct/density/view_sampling.h"

namespace sylva {
namespace {

// The initial box is this many times the scene's extent; if the frustum
// intersection still touches it, the views do not bound the object.
constexpr double kInitialBoxScale = 20.0;
// Samples along each side of a foreground rectangle when unprojecting it
// (distortion bends straight image edges).
constexpr int kEdgeSamples = 32;

struct PixelRect {
  double x0, y0, x1, y1;  // pixel edges, COLMAP convention
  bool empty = true;
};

PixelRect ForegroundRect(const FloatImage& mask) {
  SYLVA_CHECK(mask.channels() == 1);
  PixelRect rect{1e300, 1e300, -1e300, -1e300};
  for (int y = 0; y < mask.height(); ++y) {
    const float* row = mask.data() + static_cast<size_t>(y) * mask.width();
    int first = 0, last = mask.width() - 1;
    while (first < mask.width() && row[first] <= 0.0f) ++first;
    if (first == mask.width()) continue;
    while (row[last] <= 0.0f) --last;
    rect.x0 = std::min<double>(rect.x0, first);
    rect.x1 = std::max<double>(rect.x1, last + 1);
    rect.y0 = std::min<double>(rect.y0, y);
    rect.y1 = y + 1;
    rect.empty = false;
  }
  return rect;
}

// Bounds of the rectangle's boundary in normalized camera coordinates.
Eigen::AlignedBox2d NormalizedRect(const Camera& camera, const PixelRect& rect) {
  Eigen::AlignedBox2d box;
  for (int i = 0; i <= kEdgeSamples; ++i) {
    const double s = static_cast<double>(i) / kEdgeSamples;
    const double x = rect.x0 + s * (rect.x1 - rect.x0), y = rect.y0 + s * (rect.y1 - rect.y0);
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(x, rect.y0), Eigen::Vector2d(x, rect.y1),
                                     Eigen::Vector2d(rect.x0, y), Eigen::Vector2d(rect.x1, y)}) {
      box.extend(camera.CamFromImg(p));
    }
  }
  return box;
}

// Clips by n_cam . p_cam + d >= 0, expressed in world coordinates.
void ClipInCamera(const View& view, const Eigen::Vector3d& normal_in_cam, double offset,
                  ConvexPolytope* polytope) {
  const Eigen::Matrix3d rotation = view.cam_from_world.rotation.toRotationMatrix();
  polytope->Clip(rotation.transpose() * normal_in_cam,
                 normal_in_cam.dot(view.cam_from_world.translation) + offset);
}

// Whether the foreground rectangle reaches a photo's edge: the object goes
// on beyond the frame, and there it may be wider than the rectangle. An
// orthographic view is a drawing (or a rendering made to frame the object):
// its edge is the drawing's, never a cut.
bool OnTheEdge(const Camera& camera, const PixelRect& rect) {
  if (camera.IsOrthographic()) return false;
  return rect.x0 <= 0 || rect.x1 >= camera.width() || rect.y0 <= 0 || rect.y1 >= camera.height();
}

void ClipByFrustum(const ImageSet& image_set, int view_idx, const PixelRect& rect,
                   double near_distance, ConvexPolytope* polytope) {
  const View& view = image_set.views[view_idx];
  const Camera& camera = image_set.CameraOf(view);
  const Eigen::AlignedBox2d r = NormalizedRect(camera, rect);
  if (camera.IsOrthographic()) {
    ClipInCamera(view, {1, 0, 0}, -r.min().x(), polytope);
    ClipInCamera(view, {-1, 0, 0}, r.max().x(), polytope);
    ClipInCamera(view, {0, 1, 0}, -r.min().y(), polytope);
    ClipInCamera(view, {0, -1, 0}, r.max().y(), polytope);
    return;
  }
  ClipInCamera(view, {1, 0, -r.min().x()}, 0, polytope);
  ClipInCamera(view, {-1, 0, r.max().x()}, 0, polytope);
  ClipInCamera(view, {0, 1, -r.min().y()}, 0, polytope);
  ClipInCamera(view, {0, -1, r.max().y()}, 0, polytope);
  ClipInCamera(view, {0, 0, 1}, -near_distance, polytope);
}

// A box surely containing the object: around the camera centres, scaled by
// their spread and by orthographic image extents.
Box3d InitialBox(const ImageSet& image_set) {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const View& view : image_set.views) center += view.ProjectionCenter();
  center /= image_set.NumViews();
  double extent = 0.0;
  for (const View& view : image_set.views) {
    extent = std::max(extent, (view.ProjectionCenter() - center).norm());
    const Camera& camera = image_set.CameraOf(view);
    if (camera.IsOrthographic()) {
      extent = std::max({extent, camera.width() / camera.FocalLengthX(),
                         camera.height() / camera.FocalLengthY()});
    }
  }
  SYLVA_CHECK(extent > 0);
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(kInitialBoxScale * extent);
  return Box3d(center - half, center + half);
}

bool Touches(const Box3d& inner, const Box3d& outer) {
  const double tolerance = 1e-6 * outer.diagonal().norm();
  return ((inner.min() - outer.min()).array() < tolerance).any() ||
         ((outer.max() - inner.max()).array() < tolerance).any();
}

VoxelBlock CoarseBlock(const Box3d& box, int resolution) {
  VoxelBlock block;
  block.voxel_size = box.sizes().maxCoeff() / resolution;
  block.lower_corner = box.min();
  for (int a = 0; a < 3; ++a) {
    block.dims[a] = std::max(1, static_cast<int>(std::ceil(box.sizes()[a] / block.voxel_size)));
  }
  return block;
}

}  // namespace

FloatImage ForegroundMask(const FloatImage& matte, double alpha_threshold) {
  FloatImage mask(matte.width(), matte.height(), 1);
  for (size_t i = 0; i < matte.NumPixels(); ++i) {
    mask.data()[i] = matte.data()[i] > alpha_threshold ? 1.0f : 0.0f;
  }
  return mask;
}

Box3d FrustumIntersectionBounds(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                                FrameCuts* cuts) {
  const Box3d initial = InitialBox(image_set);
  ConvexPolytope closed(initial), uncut(initial);  // by every view, by the uncut ones
  const double near_distance = 1e-9 * initial.diagonal().norm();
  FrameCuts found;
  std::vector<PixelRect> rects(image_set.NumViews());
  tbb::parallel_for(0, image_set.NumViews(), [&](int v) { rects[v] = ForegroundRect(masks[v]); });
  for (int v = 0; v < image_set.NumViews(); ++v) {
    const PixelRect& rect = rects[v];
    SYLVA_CHECK_INPUT(!rect.empty, image_set.views[v].name) << "matte is empty (no foreground)";
    ClipByFrustum(image_set, v, rect, near_distance, &closed);
    if (cuts != nullptr && OnTheEdge(image_set.CameraOf(v), rect)) {
      found.views.push_back(v);
    } else {
      ClipByFrustum(image_set, v, rect, near_distance, &uncut);
    }
  }
  SYLVA_CHECK_INPUT(!closed.IsEmpty(), "mattes")
      << "the views' foreground regions do not intersect in space: cameras and mattes are "
         "inconsistent";
  const Box3d uncut_bounds = uncut.Bounds();
  // Views that frame the whole object bound it where others are cut.
  found.beyond_every_frame =
      !found.views.empty() && (static_cast<int>(found.views.size()) == image_set.NumViews() ||
                               Touches(uncut_bounds, initial));
  if (cuts != nullptr) *cuts = found;
  if (!found.views.empty() && !found.beyond_every_frame) return uncut_bounds;
  const Box3d bounds = closed.Bounds();
  SYLVA_CHECK_INPUT(!Touches(bounds, initial), "Density.bounds")
      << "the views do not bound the tree in depth (too few views, or all looking the same "
         "way); set the bounds explicitly";
  return bounds;
}

Box3d VisualHullBounds(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                       int resolution, int dissent, const ProgressTask& progress, FrameCuts* cuts) {
  SYLVA_CHECK(dissent >= 0);
  const Box3d frustum_bounds = FrustumIntersectionBounds(image_set, masks, cuts);
  const std::vector<SummedAreaTable> tables = MakeSummedAreaTables(masks);
  const VoxelBlock block = CoarseBlock(frustum_bounds, resolution);
  const std::vector<float> kept =
      dissent == 0 ? MinFootprintMeans(image_set, tables, block, progress)
                   : LowFootprintMeans(image_set, tables, block, dissent, progress);
  Box3d bounds;
  const Eigen::Vector3d voxel = Eigen::Vector3d::Constant(block.voxel_size);
  for (int64_t i = 0; i < block.NumVoxels(); ++i) {
    if (kept[i] <= 0.0f) continue;
    const Eigen::Vector3d lower =
        block.lower_corner + block.voxel_size * block.VoxelFromLinear(i).cast<double>();
    bounds.extend(lower);
    bounds.extend(lower + voxel);
  }
  SYLVA_CHECK_INPUT(!bounds.isEmpty(), "mattes")
      << "no point in space projects to foreground in every view: cameras and mattes are "
         "inconsistent";
  return bounds;
}

}  // namespace sylva
