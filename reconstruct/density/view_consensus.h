// Which views agree with the others: a guard against wrong mattes.
//
// Implicit carving keeps a voxel only if every view sees foreground there
// (thesis 3.3), so one wrong matte (inverted, half empty, of another photo)
// carves away what all the other views agree on. Before the density is
// reconstructed, every view's matte is tested against a *consensus hull*: on a
// coarse grid over the reconstruction bounds, the voxels that at most
// `allowed_dissent` views carve away (a vote instead of the strict
// intersection). A view whose matte carves away a large share of the
// consensus hull, compared with what the other views carve, disagrees with
// the others; so does a view with much foreground onto which no consensus
// voxel projects (an inverted matte carves nothing, but its "room" would be
// fitted as density). Both are distrusted: the density stage leaves them out
// and names them.
//
// A correct view also carves some of the consensus hull (the hull is fatter
// than the strict one by what each view alone carves), which is why the test
// is relative to the median view. With fewer than
// DensityOptions::view_consensus_min_views views nothing is tested: there is
// no majority to side with.
#ifndef SYLVA_RECONSTRUCT_DENSITY_VIEW_CONSENSUS_H_
#define SYLVA_RECONSTRUCT_DENSITY_VIEW_CONSENSUS_H_

#include <string>
#include <vector>

#include "core/geometry/box.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "reconstruct/density/density_options.h"

namespace sylva {

struct ViewConsensus {
  int allowed_dissent = 0;           // views that may carve a consensus voxel away
  int64_t consensus_voxels = 0;      // of the coarse grid
  std::vector<double> carved_share;  // per view: share of the consensus it carves away
  double median_carved_share = 0.0;
  // Per view: share of its foreground onto which no consensus voxel projects.
  std::vector<double> unexplained_share;
  double median_unexplained_share = 0.0;
  std::vector<bool> trusted;         // per view
  std::vector<std::string> reasons;  // per view: why it is distrusted ("" if trusted)

  int NumDistrusted() const;
};

// Views whose foreground mask (1 = foreground, as ForegroundMask makes) is
// implausible on its own: empty, or with less than 1 / kSparseForegroundRatio
// of the median view's foreground. Per view: the reason, "" if plausible.
// They would carve everything away; they take no part in the bounds.
std::vector<std::string> ScreenForegroundMasks(const std::vector<FloatImage>& masks);

// Tests every view's foreground mask against the others' consensus on a grid
// of options.hull_resolution voxels over `bounds` (DensityOptions::view_*
// fields). Views with a reason in `screened` (ScreenForegroundMasks) take no
// part and stay distrusted for that reason.
ViewConsensus AssessViewConsensus(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                                  const Box3d& bounds, const DensityOptions& options,
                                  const std::vector<std::string>& screened,
                                  const ProgressTask& progress);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_VIEW_CONSENSUS_H_
