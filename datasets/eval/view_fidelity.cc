#include "datasets/eval/view_fidelity.h"

#include <algorithm>

#include "core/util/check.h"
#include "mesh/mesh_renderer.h"
#include "reconstruct/density/opacity_projection.h"

namespace sylva {
namespace {

// Shaded pictures of the mesh are made from the coverage's own samples
// (one pass), at least this many pixels across where those samples allow:
// report.html shows them 256 px wide (they enter no score).
constexpr int kRenderSize = 256;

// How many times larger than the compared image the picture is: the
// smallest divisor of the samples per axis that makes it kRenderSize
// across, else all of them (one sample per picture pixel).
int PictureScale(int compared_size, int samples_per_axis) {
  for (int scale = 1; scale < samples_per_axis; ++scale) {
    if (samples_per_axis % scale == 0 && compared_size * scale >= kRenderSize) return scale;
  }
  return samples_per_axis;
}

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
                                                     const ViewFidelityOptions& options,
                                                     std::vector<FloatImage>* projections) {
  if (projections != nullptr) projections->resize(image_set.NumViews());
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
    const bool known = projections != nullptr && (*projections)[v].width() == view.width &&
                       (*projections)[v].height() == view.height &&
                       (*projections)[v].channels() == 1;
    view.predicted = known ? (*projections)[v] : projector.Render(image_set, v, sampling);
    if (projections != nullptr) (*projections)[v] = view.predicted;
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
  const int samples = options.mesh_samples_per_axis;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    ViewFidelity& view = (*views)[v];
    const Camera compared = DownsampledCamera(image_set.CameraOf(v), view.downsample_factor);
    const int picture_scale =
        options.render_pictures
            ? PictureScale(std::max(compared.width(), compared.height()), samples)
            : 0;
    MeshRenderer::CoverageAndRgba rendered = renderer.RenderCoverageAndRgba(
        compared, image_set.views[v].cam_from_world, samples, picture_scale, MeshRenderOptions());
    view.mesh_coverage = std::move(rendered.coverage);
    view.mesh_render = std::move(rendered.rgba);
    view.mesh_scores = CompareSilhouettes(view.mesh_coverage, view.observed,
                                          static_cast<float>(options.opacity_threshold),
                                          static_cast<float>(options.matte_threshold));
    view.has_mesh = true;
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
