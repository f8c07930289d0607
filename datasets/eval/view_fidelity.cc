#include "datasets/eval/view_fidelity.h"

#include <algorithm>

#include "core/util/check.h"
#include "mesh/mesh_renderer.h"
#include "reconstruct/density/opacity_projection.h"

namespace sylva {
namespace {

// Shaded pictures of the mesh are made at most this many pixels across:
// report.html shows them 256 px wide (they enter no score).
constexpr int kRenderSize = 256;
// Rays per pixel along each axis of the shaded pictures (2 x 2): enough to
// smooth their edges for the eye; they enter no score (the coverage uses
// ViewFidelityOptions::mesh_samples_per_axis).
constexpr int kRenderSamplesPerAxis = 2;

// A camera for the image downsampled by `factor` (box filter, partial blocks).
Camera DownsampledCamera(const Camera& camera, int factor) {
  return camera.Scaled(1.0 / factor, (camera.width() + factor - 1) / factor,
                       (camera.height() + factor - 1) / factor);
}

}  // namespace

std::vector<ViewFidelity> ComputeDensityViewFidelity(const DensityGrid& grid,
                                                     const ImageSet& image_set,
                                                     const std::vector<FloatImage>& mattes,
                                                     const std::vector<bool>& held_out,
                                                     const ViewFidelityOptions& options) {
  const OpacityProjector projector(grid);
  const Eigen::Vector3d center =
      grid.IsEmpty() ? grid.origin() : Eigen::Vector3d(grid.ActiveWorldBounds().center());
  std::vector<ViewFidelity> views;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    const ViewSampling sampling =
        MakeViewSampling(image_set, v, center, grid.voxel_size(), options.pixels_per_voxel, 1);
    ViewFidelity view;
    view.name = image_set.views[v].name;
    view.held_out = held_out[v];
    view.downsample_factor = sampling.factor;
    view.width = sampling.width();
    view.height = sampling.height();
    view.predicted = projector.Render(image_set, v, sampling);
    view.observed = DownsampleBox(mattes[v], sampling.factor);
    view.scores = CompareSilhouettes(view.predicted, view.observed,
                                     static_cast<float>(options.opacity_threshold),
                                     static_cast<float>(options.matte_threshold));
    views.push_back(std::move(view));
  }
  return views;
}

void AddMeshViewFidelity(const TriangleMesh& mesh, const ImageSet& image_set,
                         const ViewFidelityOptions& options, std::vector<ViewFidelity>* views) {
  SYLVA_CHECK(static_cast<int>(views->size()) == image_set.NumViews());
  if (mesh.NumTriangles() == 0) return;
  const MeshRenderer renderer(mesh);
  MeshRenderOptions shading;
  shading.samples_per_axis = kRenderSamplesPerAxis;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    ViewFidelity& view = (*views)[v];
    const Camera& camera = image_set.CameraOf(v);
    const Rigid3d& pose = image_set.views[v].cam_from_world;
    view.mesh_coverage = renderer.RenderCoverage(DownsampledCamera(camera, view.downsample_factor),
                                                 pose, options.mesh_samples_per_axis);
    view.mesh_scores = CompareSilhouettes(view.mesh_coverage, view.observed,
                                          static_cast<float>(options.opacity_threshold),
                                          static_cast<float>(options.matte_threshold));
    view.has_mesh = true;
    if (options.render_pictures) {
      const int factor =
          std::max(1, (std::max(camera.width(), camera.height()) + kRenderSize - 1) / kRenderSize);
      view.mesh_render = renderer.RenderRgba(DownsampledCamera(camera, factor), pose, shading);
    }
  }
}

FidelityGroup SummariseViews(const std::vector<ViewFidelity>& views, bool held_out, bool mesh) {
  FidelityGroup group;
  double iou = 0.0, min_iou = 1.0, precision = 0.0, recall = 0.0;
  for (const ViewFidelity& view : views) {
    if (view.prior || view.held_out != held_out || (mesh && !view.has_mesh)) continue;
    const SilhouetteScores& scores = mesh ? view.mesh_scores : view.scores;
    ++group.num_views;
    iou += scores.iou;
    min_iou = std::min(min_iou, scores.iou);
    precision += scores.precision;
    recall += scores.recall;
  }
  if (group.num_views == 0) return group;  // no scores: absent, not 0
  group.mean_iou = iou / group.num_views;
  group.min_iou = min_iou;
  group.mean_precision = precision / group.num_views;
  group.mean_recall = recall / group.num_views;
  return group;
}

}  // namespace sylva
