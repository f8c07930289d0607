// Branch radii measured in the mattes.
//
// The pipe model (mesh/allometry.h) fixes the ratios of the radii from the
// particle count, not their sizes: on a plant whose particles split into
// hundreds of tips it makes every side stem a hair, although the photos
// show its width plainly. Here each skeleton edge is projected into the
// views that see it side-on, its centre line is looked for in the matte
// near the projection, and the matte's half-width there (the distance
// transform's ridge) is taken to world units at the edge's depth. Over the
// views, a low quantile: overlapping branches, leaves and foreshortening
// only ever widen a branch in a view, never narrow it.
//
// The measurement scales the pipe model instead of replacing it node by
// node: each branch axis with enough measured edges is scaled by the median
// ratio measured / prior of its edges (the model's smooth taper kept), an
// axis the mattes do not resolve takes its parent axis' scale, and no
// branch gets thicker than the pipe model allows beside its parent
// (d^Delta <= d_parent^Delta at the junction), which bounds branches hidden
// in foliage by the trunk measured below it.
#ifndef SYLVA_RECONSTRUCT_MEASUREMENT_BRANCH_WIDTH_H_
#define SYLVA_RECONSTRUCT_MEASUREMENT_BRANCH_WIDTH_H_

#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"

namespace sylva {

// The label MeasureBranchRadii writes into SkeletonGraph::radius_source when
// it measured at least one axis.
inline constexpr const char* kMattesMeasured = "measured in the mattes";

struct BranchWidthOptions {
  // When to measure: "auto" = for leafless plants only (on a leafy tree the
  // mattes show the foliage around a branch, not its wood: measured there,
  // the synthetic demo's branches came out 1.4x too thick and its bark
  // could not be joined), "on", or "off" (the pipe model's prior stays).
  std::string mode = "auto";
  // A pixel is foreground at this alpha or more.
  double matte_threshold = 0.5;
  // The quantile over the views that measure an edge (0 = the narrowest).
  double view_quantile = 0.25;
  // Views needed to measure an edge.
  int min_views = 2;
  // An edge is measured in a view only when it is seen at least this much
  // side-on: its projected length over its length seen square-on, in (0, 1]
  // (0.5 = at least 30 degrees from the line of sight).
  double min_side_on = 0.5;
  // How far across the projected edge (pixels) its centre line is looked for:
  // registration and skeleton positions are off by a pixel or two.
  double search_pixels = 3.0;
  // An axis is scaled by its own measurement when at least this share of its
  // edges were measured (and at least 2 edges); else by its parent's scale.
  double min_measured_share = 0.3;

  // Throws InputError("BranchWidth.<field>", ...) naming the violated constraint.
  void Check() const;
};

struct BranchWidthSummary {
  int num_axes = 0;
  int measured_axes = 0;       // scaled by their own measurement
  double measured_length = 0;  // world units, in measured axes
  double total_length = 0;
  double trunk_scale = 1.0;  // the trunk axis' measured / prior (1 if not measured)
  std::string BriefReport() const;
};

// Scales `skeleton`'s radii (a pipe-model prior, see above) to the widths
// the `mattes` (one per view of `views`, same size as their cameras) show.
// `leafless` decides mode "auto". When `keep_trunk` is set
// (a trunk radius given by the user), the trunk axis keeps its radii. Sets
// radius_source to kMattesMeasured if any axis was measured.
BranchWidthSummary MeasureBranchRadii(const ImageSet& views, const std::vector<FloatImage>& mattes,
                                      bool leafless, bool keep_trunk,
                                      const BranchWidthOptions& options, SkeletonGraph* skeleton);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MEASUREMENT_BRANCH_WIDTH_H_
