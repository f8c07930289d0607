// Removing branches the photos contradict. The density's visual hull keeps
// "ghost" regions that project inside every matte without holding any tree
// (2-3 % of a synthetic tree's opacity); particles seeded there flow to the
// trunk along paths that cross background in some view. A thin branch axis
// whose path lies largely outside a matte is removed with everything it
// carries, and its strands are taken off its ancestors (pipe model stays
// consistent).
#ifndef SYLVA_SIMULATE_SKELETON_PRUNING_H_
#define SYLVA_SIMULATE_SKELETON_PRUNING_H_

#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"
#include "simulate/painted_density.h"

namespace sylva {

struct MattePruningOptions {
  // Only axes carrying at most this fraction of the root's strands are
  // tested; thicker limbs are trusted. 0 disables pruning.
  double max_strand_fraction = 0.05;
  // An axis is removed when more than this fraction of its samples projects
  // onto matte background in some view.
  double max_outside_fraction = 0.5;
  // A sample is on background if the largest matte value in its 3 x 3 pixel
  // neighbourhood is below this (lenient with thin branches and small
  // registration errors); alpha.
  double matte_threshold = 0.1;
  // Distance between samples along an axis, as a fraction of the tree height.
  double sample_spacing_fraction = 0.005;

  // Throws InputError("Skeleton.<field>", ...).
  void Check() const;
};

struct MattePruningSummary {
  int tested_axes = 0;
  int removed_axes = 0;  // tested axes that were removed (what they carried goes too)
  int removed_nodes = 0;
  int removed_strands = 0;
  int painted_axes = 0;  // thin axes kept untested: they carry painted density
  std::string BriefReport() const;
};

// `mattes` are one per view of `views`. Axes that carry `painted` density
// (optional) are kept. The result keeps node order (parents before
// children), strands consistent and orders reassigned.
SkeletonGraph PruneBranchesOutsideMattes(const SkeletonGraph& skeleton, const ImageSet& views,
                                         const std::vector<FloatImage>& mattes,
                                         const MattePruningOptions& options,
                                         MattePruningSummary* summary,
                                         const PaintedDensity* painted = nullptr);

}  // namespace sylva

#endif  // SYLVA_SIMULATE_SKELETON_PRUNING_H_
