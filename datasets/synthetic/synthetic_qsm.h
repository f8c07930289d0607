// Laser-scan-like QSM cylinder tables (core/io/qsm_io.h) of the synthetic
// trees: the ground truth for meshing large TreeQSM tables.
//
// The ITSMe tables in datasets/itsme-qsm have 60-210 cylinders; a TreeQSM
// model of a whole scanned tree has thousands, with what those small ones
// hardly show: branches thinning to millimetres, cylinders a few radii long
// whose axes jitter from one to the next (each is fitted to its own patch of
// noisy points), and fragments the reconstruction could not attach (extra
// roots). GenerateSyntheticQsm makes such a table from the synthetic tree
// (datasets/synthetic/synthetic_tree.h):
//   - every branch axis of the skeleton is cut into cylinders of
//     cylinder_length_radii x the local radius, clamped to
//     [min_cylinder_length, max_cylinder_length], along its polyline;
//   - the cut points wander by up to position_noise x the local radius, the
//     radii by +-radius_noise (relative), floored at the tree's min_radius;
//   - each cylinder starts overlap_radii x its radius back inside the
//     previous one (TreeQSM's successive cylinders overlap by a few mm);
//   - a branch's first cylinder starts child_start_depth x the parent's
//     radius inside the parent (TreeQSM: a branch starts inside its parent
//     cylinder) and hangs from the parent cylinder holding the junction;
//   - `fragments` branches (order >= 1, drawn by seed) lose their parent:
//     parent_id 0, as TreeQSM leaves detached pieces.
// Ids are 1, 2, ... axis by axis (trunk first), parents before children;
// branch = the axis' 1-based index, branch_order = its order. Sources read
// "ground truth" (positions, radii and branching are the generator's), units
// "m". The same options and seed give the same table.
#ifndef SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_QSM_H_
#define SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_QSM_H_

#include <cstdint>

#include "core/io/qsm_io.h"
#include "datasets/synthetic/synthetic_tree.h"

namespace sylva {

struct SyntheticQsmOptions {
  // The tree; by default the synthetic tree with twigs thinning to 1 mm
  // radius (2 mm diameter) at the tips, as scanned small branches.
  SyntheticTreeOptions tree = ThinTwigTree();
  // Cylinder length in radii of the local branch, and its bounds in metres
  // (0 < min <= max).
  double cylinder_length_radii = 4.0;
  double min_cylinder_length = 0.03;
  double max_cylinder_length = 0.3;
  // Noise of the cut points (radii of the local branch, >= 0) and of the
  // radii (relative, in [0, 1)).
  double position_noise = 0.3;
  double radius_noise = 0.1;
  // Overlap of successive cylinders, in radii (>= 0, < 1).
  double overlap_radii = 0.1;
  // How deep a branch's first cylinder starts inside its parent, as a
  // fraction of the parent's radius (0 = on its surface, 1 = on its axis).
  double child_start_depth = 0.8;
  // Branches detached as extra roots (>= 0; at most the tree's branches).
  int fragments = 4;

  static SyntheticTreeOptions ThinTwigTree();
  // Throws InputError naming the first violated constraint.
  void Check() const;
};

QsmModel GenerateSyntheticQsm(const SyntheticQsmOptions& options, uint64_t seed);

}  // namespace sylva

#endif  // SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_QSM_H_
