// Structure finer than the voxels. A grid whose voxels are wider than a
// plant's stems cannot hold the stems: they are carved away or smeared into
// faint voxels, and the skeleton never sees them. Before the grid is made,
// the mattes tell how much of the tree is thin: the share of the centre
// lines of their foreground (the ridge of its distance transform) that lies in structures
// thinner than a voxel, i.e. farther than half a voxel from what survives a
// morphological opening with a disk one voxel across (each voxel as wide as
// it appears in that photo at the tree's distance). Centre lines measure
// length, so a long thin stem counts for what it is beside a bulky pot, and
// the short spurs of a leafy crown's ragged outline, which end next to the
// crown, do not count as thin. The density stage refines its grid until that
// share is small enough, up to a cap, and says so when the cap is reached.
#ifndef SYLVA_RECONSTRUCT_DENSITY_THIN_STRUCTURE_H_
#define SYLVA_RECONSTRUCT_DENSITY_THIN_STRUCTURE_H_

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"

namespace sylva {

class ThinStructureProbe {
 public:
  // Looks at the mattes (alpha >= 0.5 is foreground) of up to `max_views`
  // views evenly spread over `image_set`; finds their centre lines once.
  ThinStructureProbe(const ImageSet& image_set, const std::vector<FloatImage>& mattes,
                     int max_views);
  ~ThinStructureProbe();

  // Share of the centre-line length thinner than a voxel of `voxel_size`
  // world units placed at `center_in_world`; 0 without foreground, or where a
  // voxel is under two pixels wide in every view looked at.
  double ThinShare(const Eigen::Vector3d& center_in_world, double voxel_size) const;

  // Whether the photos can show structure as fine as a voxel of
  // `voxel_size`: it is at least two pixels wide in most views looked at.
  bool Resolvable(const Eigen::Vector3d& center_in_world, double voxel_size) const;

 private:
  struct View;
  const ImageSet& image_set_;
  std::vector<std::unique_ptr<View>> views_;
};

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_THIN_STRUCTURE_H_
