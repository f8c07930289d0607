// Automatic reconstruction bounds: the bounding box of the visual hull of the
// mattes (the region that projects to foreground in every view that sees it).
#ifndef SYLVA_RECONSTRUCT_DENSITY_VISUAL_HULL_H_
#define SYLVA_RECONSTRUCT_DENSITY_VISUAL_HULL_H_

#include <vector>

#include "core/geometry/box.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"

namespace sylva {

// Binary foreground mask (1 where matte > alpha_threshold) of a matte.
FloatImage ForegroundMask(const FloatImage& matte, double alpha_threshold);

// Views whose foreground reaches the edge of their image: the object goes
// on beyond that frame.
struct FrameCuts {
  std::vector<int> views;  // indices into the image set
  // Every view cuts the object (or those that do not leave it unbounded):
  // no view frames it whole, so the frames bound it and what lies beyond
  // them is left out.
  bool beyond_every_frame = false;
};

// Intersection of the frusta through each mask's foreground bounding
// rectangle; a bounded box, or InputError if the views do not bound the
// object (e.g. all parallel) or do not intersect. A view whose foreground
// reaches its image's edge bounds nothing here (the object goes on beyond
// its frame, where it may be wider than the foreground rectangle: only the
// carving uses that view, where it sees), unless every view is cut so:
// then all bound it and `cuts` says so. Orthographic views (drawings) are
// never cut. Null `cuts`: every view bounds it (the frames always bound the
// object).
Box3d FrustumIntersectionBounds(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                                FrameCuts* cuts = nullptr);

// The visual hull's bounding box: frustum intersection refined by carving a
// grid of `resolution` voxels (longest side) with the masks' summed-area
// tables. Conservative: contains every point that projects to foreground in
// all views that see it but `dissent` (a point beyond a view's frame is not
// seen by it): the carving's allowance for mattes that miss a thin branch's
// tip, which a hull of every view would cut from the bounds. Throws
// InputError if nothing survives.
Box3d VisualHullBounds(const ImageSet& image_set, const std::vector<FloatImage>& masks,
                       int resolution, int dissent, const ProgressTask& progress,
                       FrameCuts* cuts = nullptr);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_DENSITY_VISUAL_HULL_H_
