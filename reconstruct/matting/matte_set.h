// Checks of a whole photo set's mattes, made before any camera is known (the
// matte stage; the density stage tests the mattes again against the cameras,
// reconstruct/density/view_consensus.h). Two things one photo alone cannot
// tell:
//
//  1. Static structure of a fixed-camera rig. In a phenotyping cabin the
//     plant turns on a turntable in front of a fixed camera: the cabin's
//     frame, rails, lamps and pot holder stay at the same pixels in every
//     photo, and backdrop keying takes them for foreground because they are
//     not the backdrop's colour. A pixel that is foreground and looks the same
//     (within static_color_tolerance of the per-pixel median photo) in at
//     least static_photo_fraction of the photos of one size is static. The
//     subject's parts on the rotation axis are static too (a trunk or stem
//     looks alike from every side): a connected piece of static pixels that
//     touches the foreground that moves and does not reach the image border
//     stays; every other static piece is the rig's and becomes background in
//     every photo. A stem joined to the rig through static pixels (a pot of
//     the stem's colour on a holder on rails) goes with the rig up to where
//     the moving leaves begin. When nearly all foreground is static (photos
//     of a scene that does not move), the test says so and removes nothing.
//  2. Implausible mattes: a matte whose foreground covers most of the image
//     border (a tree is framed with background around it), or whose
//     foreground share is far from the other photos' median (an inverted
//     matte: the room taken for the tree). The matte stage tries to repair
//     them (MatteVerdict) and names what it did.
//
// All images here are small copies of the photos and mattes (longest side
// about MatteSetOptions::analysis_size pixels), one per photo.
#ifndef SYLVA_RECONSTRUCT_MATTING_MATTE_SET_H_
#define SYLVA_RECONSTRUCT_MATTING_MATTE_SET_H_

#include <array>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/util/warning.h"
#include "reconstruct/matting/matting.h"

namespace sylva {

struct MatteSetOptions {
  // --- Static structure ---
  bool remove_static = true;
  // Photos of one size needed before pixels can be called static (>= 3).
  int static_min_photos = 5;
  // A pixel is static structure when it is foreground and unchanged in at
  // least this share of the photos of its size, in (0.5, 1].
  double static_photo_fraction = 0.8;
  // "Unchanged": every RGB channel within this of the per-pixel median photo
  // (colours in [0, 1]; JPEG noise and flicker of the lamps stay below).
  double static_color_tolerance = 0.08;
  // Static structure is grown by this many analysis pixels (its blended
  // edges), in [0, 10].
  int static_margin_px = 2;
  // If less than this share of the foreground moves between photos, the
  // scene itself does not move (the same view photographed again): nothing
  // is removed, and a warning says why. In [0, 1).
  double static_min_moving_share = 0.05;

  // --- Implausible mattes ---
  // A matte whose foreground (alpha >= 0.5) covers more than this share of
  // the image border is implausible, in (0, 1].
  double max_border_share = 0.5;
  // A matte whose foreground share is more than this many times the median
  // photo's, or less than its inverse, is implausible (> 1). Needs at least
  // 3 photos.
  double max_foreground_ratio = 4.0;

  // Longest side of the copies analysed, in pixels (>= 32).
  int analysis_size = 512;

  // Throws InputError naming the first violated constraint
  // ("MatteSet.static_photo_fraction must be ...").
  void Check() const;
};

// The integer factor that box-downsamples a width x height photo to at most
// options.analysis_size pixels on its longest side.
int MatteSetFactor(int width, int height, const MatteSetOptions& options);

// The analysis copy of a matte: each pixel the largest value of its
// factor x factor block, so that structure thinner than a copy's pixel
// (a cabin's window frame, a stem) is still there.
FloatImage SmallMatte(const FloatImage& matte, int factor);

// Static structure per photo (1 = structure, 0 = not; the analysis copy's
// size), or empty images where none was found. `small_photos` (RGB or RGBA)
// and `small_mattes` (one channel) are the analysis copies, in the same
// order; photos are grouped by size. Adds a "static-structure" warning per
// group with structure, or "static-scene" when the scene does not move.
std::vector<FloatImage> FindStaticStructure(const std::vector<FloatImage>& small_photos,
                                            const std::vector<FloatImage>& small_mattes,
                                            const MatteSetOptions& options,
                                            std::vector<Warning>* warnings);

// What one matte looks like.
struct MatteShape {
  double foreground_share = 0.0;  // of the image's pixels, alpha >= 0.5
  double border_share = 0.0;      // of the image's border pixels, alpha >= 0.5
};
MatteShape MeasureMatte(const FloatImage& matte);

// Whether a matte of this shape is implausible beside `median_foreground_share`
// (the set's median; <= 0 when the set is too small to compare); the reason
// ("" if plausible).
std::string ImplausibleMatteReason(const MatteShape& shape, double median_foreground_share,
                                   const MatteSetOptions& options);

// A new matte for a photo whose own matte (`own`, made with `options`) is
// implausible: the subject is foreground against the backdrop the other
// photos agree on (`backdrop_rgb`, in [0, 1]) and against whatever this
// photo's own matting took for backdrop (a room its border saw), so the new
// matte is, per pixel, the smaller of `own` and the photo keyed against
// `backdrop_rgb` (with the same painted hint, which may be empty).
FloatImage RepairMatte(const FloatImage& photo, const FloatImage& hint, const FloatImage& own,
                       const std::array<double, 3>& backdrop_rgb, const MattingOptions& options);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_MATTE_SET_H_
