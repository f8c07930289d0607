// Puts a registration into sylva's world frame: up = +Z, the tree's base (the
// bottom of the trunk, or of its pot) at the origin, and metres (or the user's
// unit) when the tree's height is known.
//
// Structure from motion (COLMAP) and hand-made registrations come in an
// arbitrary frame: COLMAP's is set by its first two photos, with an arbitrary
// scale; ROMI's scanner frame has +Z pointing down, in millimetres. Later
// stages need to know which way is up (particles flow down to the base, the
// trunk grows up) and where the base is, so the frame is normalised once,
// right after registration:
//
//   WorldFrame frame = EstimateWorldFrame(cameras, mattes, WorldFrameOptions());
//   ImageSet upright = TransformCameras(cameras, frame);
//
// Up (options.up = "auto"):
//   - a ring of cameras, or an arc of one (photos taken walking around the
//     tree at about the same height): the normal of the plane that fits the
//     camera centres best, pointing the way the cameras' image-up vectors
//     point;
//   - otherwise (few photos, or centres not on a plane): the direction
//     perpendicular to all the cameras' x axes, which are level when photos
//     are taken upright (no roll), whatever their pitch; a systematic roll
//     (ROMI's camera has ~4 degrees) biases it when the photos cover only an
//     arc. With one camera, its image up (-y).
// Base (options.base = "auto", needs mattes of at least 2 views):
//   - in each matte, the lowest band of foreground along the image's up
//     direction, as a pixel; the rays through those pixels are triangulated
//     (the least-squares closest point to all rays);
//   - the point then slides along up to the bottom of the matte-consistent
//     region, the points that project into the foreground of (nearly) all
//     the views that see them (a visual hull along one vertical line).
//   The top is triangulated the same way from the highest foreground bands;
//   the tree height is the distance from the base to the top along up.
//   Without mattes, the base is the point the cameras' optical axes pass
//   closest to (the centre of attention, not the trunk's bottom).
// Scale: known_height / measured height when known_height > 0 (units as given),
// otherwise the registration's own scale (units "arbitrary").
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_WORLD_FRAME_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_WORLD_FRAME_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/geometry/sim3.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"

namespace sylva {

// The axes WorldFrame.up names, besides auto and keep.
inline const char* const kUpAxisNames[] = {"+x", "-x", "+y", "-y", "+z", "-z"};

struct WorldFrameOptions {
  // Which way is up in the input frame:
  //   "auto":  estimated from the cameras (see above);
  //   "+x", "-x", "+y", "-y", "+z", "-z": that axis of the input frame points
  //            up (ROMI's scanner frame: "-z"); the other axes are kept as
  //            far as a quarter or half turn allows;
  //   "keep":  the input frame is already upright (+z up).
  std::string up = "auto";
  // Where the origin goes: "auto" (the tree's base, see above) or "keep"
  // (the input frame's origin).
  std::string base = "auto";
  // The tree's real height (base to top) in `units`; 0 = unknown: the scale
  // is kept and the units are "arbitrary". Needs mattes.
  double known_height = 0.0;
  // The unit of known_height ("m", "mm", ...), recorded in the result.
  std::string units = "m";

  // A matte pixel is foreground where alpha exceeds this.
  double matte_threshold = 0.5;
  // Mattes are analysed box-downsampled to at most this many pixels on their
  // longer side (speed; one such pixel is the precision of the base).
  int matte_working_size = 400;
  // Foreground parts (4-connected) smaller than this fraction of the largest
  // part of their matte are ignored, so specks below the tree do not pass
  // for its base.
  double min_part_fraction = 0.02;
  // The lowest (highest) band of a matte: foreground pixels within this
  // fraction of the foreground's extent along image-up from its bottom (top).
  double band_fraction = 0.02;
  // A point belongs to the matte-consistent region when the mattes of at
  // least this fraction of the views that see it cover it (1 = the visual
  // hull; lower tolerates loose registration and matting errors).
  double consensus = 0.8;

  // The camera centres form a ring (or an arc of one) when there are at
  // least ring_min_views and their spread across the best-fit plane is at
  // most ring_max_thickness times their narrower spread within it: the
  // plane's tilt is then known to about atan(ring_max_thickness). A line of
  // cameras has no such plane.
  int ring_min_views = 5;
  double ring_max_thickness = 0.1;
  // A ring whose normal leans more than this from the cameras' upright
  // direction (degrees) is not horizontal: the cameras' direction is used.
  double ring_max_tilt_degrees = 45.0;

  // Throws InputError("WorldFrame.<field>", ...) for the first invalid field.
  void Check() const;
};

// The similarity that takes the input ("model") frame to sylva's world frame,
// and what was found on the way.
struct WorldFrame {
  // point_in_world = scale * (rotation * point_in_model) + translation.
  Sim3d world_from_model;
  // Up and the tree's base, in the input frame (up has unit length).
  Eigen::Vector3d up_in_model = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d base_in_model = Eigen::Vector3d::Zero();
  // Base to top along up, in world units; 0 if it was not measured (no
  // mattes, or base "keep" without mattes).
  double tree_height = 0.0;
  // World units: WorldFrameOptions::units when known_height was given, else
  // "arbitrary".
  std::string units = "arbitrary";
  // How up and the base were found, e.g. "camera ring (72 views)",
  // "mattes (72 views)", "option -z".
  std::string up_source;
  std::string base_source;

  // One line: "up from camera ring (72 views), base from mattes (72 views),
  // height 419 mm, scale 1".
  std::string BriefReport() const;
};

// Estimates the world frame of `cameras`. `mattes` holds one alpha matte (one
// channel) per view, in the order of cameras.views, at the photo's size or
// any size of the same aspect ratio; it may be empty (then the base is only
// approximate and the height unknown), and an empty image skips that view.
// Throws InputError for bad options, mattes that do not fit their views, or
// known_height > 0 without a measurable height.
WorldFrame EstimateWorldFrame(const ImageSet& cameras, const std::vector<FloatImage>& mattes,
                              const WorldFrameOptions& options);

// `cameras` moved into the world frame: every pose, and the sparse points.
// Pinhole intrinsics are unchanged; orthographic cameras' pixels per world
// unit are divided by the frame's scale.
ImageSet TransformCameras(const ImageSet& cameras, const WorldFrame& frame);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_WORLD_FRAME_H_
