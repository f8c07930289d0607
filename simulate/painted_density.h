// Density a person painted in (thesis 3.3, "sketched density";
// reconstruct/density/density_edits.h): opacity added on a photo where the
// photo showed none. It is the person's word that the tree is there, so the
// rules that remove thin wood the photos do not support (matte pruning,
// simulate/skeleton_pruning.h; bare sticks and branches at the trunk's foot,
// simulate/skeleton_consolidation.h) keep the wood that carries it: without
// this, a ball of density painted apart from the crown was flowed to the base
// and then every branch to it was removed, and the tree never grew there.
#ifndef SYLVA_SIMULATE_PAINTED_DENSITY_H_
#define SYLVA_SIMULATE_PAINTED_DENSITY_H_

#include <Eigen/Core>
#include <vector>

#include "core/types/density_grid.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/types/skeleton_graph.h"

namespace sylva {

class PaintedDensity {
 public:
  // `added` are one per view of `views`: the opacity the edits added over
  // the computed matte (reconstruct/density/density_edits.h: AddedOpacity), or an empty image for a
  // view without edits. A pixel counts as painted in from `min_added` (alpha).
  PaintedDensity(const DensityGrid& density, const ImageSet& views,
                 const std::vector<FloatImage>& added, float min_added = 0.5f);

  // False when no view has painted-in pixels.
  bool Any() const { return any_; }

  // True if `point` (world) holds density and projects onto painted-in
  // pixels in some view.
  bool Contains(const Eigen::Vector3d& point) const;

  // Per node of `skeleton`: 1 if the node or one of its descendants lies in
  // painted density (the wood that carries it to the root), else 0.
  std::vector<char> CarryingWood(const SkeletonGraph& skeleton) const;

 private:
  const DensityGrid& density_;
  const ImageSet& views_;
  const std::vector<FloatImage>& added_;
  float min_added_;
  bool any_ = false;
};

}  // namespace sylva

#endif  // SYLVA_SIMULATE_PAINTED_DENSITY_H_
