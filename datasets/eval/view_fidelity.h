// View fidelity: how well a reconstruction reproduces the mattes, view by
// view (thesis 7.2.2 uses silhouette precision and recall): the density
// grid's projected opacity and the tree mesh's rendered coverage against each
// view's matte, compared at about the grid's resolution; and the scores of a
// group of views (the input views, the held-out ones).
//
// The pictures compared come from the density system's forward model
// (reconstruct/density/opacity_projection.h) and the mesh renderer
// (mesh/mesh_renderer.h): sylva_eval links both privately (they do not
// depend on it; only their tests do).
#ifndef SYLVA_DATASETS_EVAL_VIEW_FIDELITY_H_
#define SYLVA_DATASETS_EVAL_VIEW_FIDELITY_H_

#include <optional>
#include <string>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/triangle_mesh.h"
#include "core/util/warning.h"
#include "datasets/eval/silhouette_metrics.h"

namespace sylva {

struct ViewFidelityOptions {
  // A pixel of the projected density or rendered mesh is foreground at this
  // opacity (coverage) or more.
  double opacity_threshold = 0.5;
  // A matte pixel is foreground at this alpha or more.
  double matte_threshold = 0.5;
  // Mattes and projections are compared after downsampling so that a voxel
  // covers about this many pixels across.
  double pixels_per_voxel = 1.0;
  // Rays per compared pixel along each axis when rendering the mesh.
  int mesh_samples_per_axis = 4;
  // Keep a shaded picture of the mesh from each view (mesh_render).
  bool render_pictures = true;
};

struct ViewFidelity {
  std::string name;
  bool held_out = false;
  // A prior, not an observation: a view the reconstruction was given but no
  // camera took (a single drawing's virtual side view, whose matte is the
  // drawing's silhouette made up as the crown's depth). Compared and shown,
  // but in neither group's figures.
  bool prior = false;
  int downsample_factor = 1;
  int width = 0, height = 0;  // of the compared (downsampled) images
  SilhouetteScores scores;    // the density's projection
  FloatImage predicted;       // projected opacity
  FloatImage observed;        // downsampled matte
  bool has_mesh = false;
  SilhouetteScores mesh_scores;  // the mesh's rendered silhouette
  FloatImage mesh_coverage;
  FloatImage mesh_render;  // shaded RGBA picture of the mesh from this view
  // The stages' warnings about this view (a distrusted or repaired matte);
  // filled by the report, not by the comparison.
  std::vector<Warning> warnings;
};

// The scores of a group of views; absent (not 0) when the group has none.
struct FidelityGroup {
  int num_views = 0;
  std::optional<double> mean_iou, min_iou, mean_precision, mean_recall;
};

// Projects `grid` into every view of `image_set` (one ray per downsampled
// pixel, at options.pixels_per_voxel) and compares with `mattes` (full
// resolution, one per view); `held_out` flags each view. `projections`
// (optional) carries the projections from an earlier call on the same grid,
// cameras and options: a view's is used where it has the compared size,
// else it is computed; on return it holds every view's.
std::vector<ViewFidelity> ComputeDensityViewFidelity(
    const DensityGrid& grid, const ImageSet& image_set, const std::vector<FloatImage>& mattes,
    const std::vector<bool>& held_out, const ViewFidelityOptions& options,
    std::vector<FloatImage>* projections = nullptr);

// Renders `mesh` (Embree) from every view of `image_set` at the resolution
// each view of `views` (ComputeDensityViewFidelity's) was compared at, and
// compares its coverage with the matte; also keeps a shaded picture of each
// view (if options.render_pictures). Nothing for an empty mesh.
void AddMeshViewFidelity(const TriangleMesh& mesh, const ImageSet& image_set,
                         const ViewFidelityOptions& options, std::vector<ViewFidelity>* views);

// The scores of `views` that are held out (or not), of the density (or of
// the mesh: views with has_mesh only); prior views are in neither group.
FidelityGroup SummariseViews(const std::vector<ViewFidelity>& views, bool held_out, bool mesh);

}  // namespace sylva

#endif  // SYLVA_DATASETS_EVAL_VIEW_FIDELITY_H_
