// Where a view's livewire paths end (TraceAttractorGraph's `target`): the
// tree base projected into the photo. When the base is out of frame (a
// close-up), the paths end where the tree leaves the photo nearest to it;
// when it is behind the camera, the view gets no traced graph.
#ifndef SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_TARGET_H_
#define SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_TARGET_H_

#include <Eigen/Core>
#include <string>

#include "core/types/float_image.h"
#include "core/types/image_set.h"

namespace sylva {

struct LivewireTarget {
  bool found = false;                                        // false: the base is behind the camera
  Eigen::Vector2d point_in_image = Eigen::Vector2d::Zero();  // pixels
  // Why the target is not the projected base, if it is not ("" otherwise).
  std::string note;
};

// The target of view `view_idx` of `views` for the tree base
// `base_in_world`: its projection if that is inside the image ([0, width] x
// [0, height], pixels), else the centre of the foreground pixel of `matte`
// (value >= matte_threshold; the photo's size) nearest to it. InputError if
// the base is out of frame and the matte has no foreground pixel.
LivewireTarget ChooseLivewireTarget(const ImageSet& views, int view_idx,
                                    const Eigen::Vector3d& base_in_world, const FloatImage& matte,
                                    double matte_threshold);

// The centre of the foreground pixel (matte >= threshold) nearest to
// `point_in_image` (ties: the first in row order). InputError if the matte
// has none.
Eigen::Vector2d NearestForeground(const FloatImage& matte, const Eigen::Vector2d& point_in_image,
                                  double threshold);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_TARGET_H_
