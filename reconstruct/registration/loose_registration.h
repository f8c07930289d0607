// Loose (manual) registration of 2-4 photos of a tree, for when structure
// from motion fails (thesis 3.3: two orthographic views at a right angle are
// enough; "we do not need an exact registration of these images").
//
//   LooseSetup setup = ReadLooseSetup("loose.json");            // loose_setup_io.h
//   ImageSet initial = InitialLooseCameras(setup, sizes, mattes, {}, &init_summary);
//   LooseRefinement refined = RefineLooseCameras(setup, initial, {});
//   // refined.image_set: cameras in sylva's world frame; refined.summary.BriefReport()
//
// 1. InitialLooseCameras puts each camera on a circle around the vertical axis
//    at the user's azimuth / elevation / roll, looking at the tree, and picks
//    its scale (orthographic pixels per unit) or distance (perspective) so that
//    the tree's base lands at the world origin and its top at tree_height
//    above it in every photo. Base and top pixels come from the "base" and
//    "top" points where clicked, else from the photo's matte (lowest and
//    highest foreground rows), else from a fixed guess (the tree fills the
//    middle of the photo; reported as a warning).
// 2. RefineLooseCameras adjusts every camera and the named 3D points with
//    Ceres to minimise the reprojection error of the clicked points (robust
//    Huber, then Cauchy loss), with weak priors tying each camera's angles to the user's
//    values and its focal length / scale to the initial one. Unknowns per
//    camera: azimuth, elevation, roll (radians), the translation of
//    cam_from_world (2 components for orthographic cameras: the third does
//    not change the image) and the scale (orthographic, pixels per unit) or
//    focal length (perspective, pixels); the principal point stays at the
//    image centre. Gauge: "base" is held at the origin; the first photo's
//    azimuth is held at the user's value; the scale is fixed by holding the
//    "top" point at z = tree_height when both are given, else by holding the
//    first photo's scale (orthographic) or its depth of the origin
//    (perspective) at the initial value; the world's tilt (which way is up)
//    comes from the elevation and roll priors.
//
// Two orthographic views cannot determine the angle between them from point
// correspondences (Ullman's two-view ambiguity of orthographic projection):
// their relative azimuth stays at the user's values, held by the prior; the
// summary says so. Three or more views, or perspective views, determine it.
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_REGISTRATION_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_REGISTRATION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "reconstruct/registration/loose_setup.h"

namespace sylva {

// --- Camera angles -------------------------------------------------------

// The rotation cam_from_world of a camera looking along azimuth / elevation /
// roll (degrees; meanings as in LoosePhoto): roll 0 keeps the world's +Z
// pointing up in the image (as LookAt with up = +Z does).
Eigen::Quaterniond LooseCamFromWorld(double azimuth_deg, double elevation_deg, double roll_deg);
// The inverse: (azimuth in (-180, 180], elevation, roll) in degrees.
Eigen::Vector3d LooseAnglesDeg(const Eigen::Quaterniond& cam_from_world);

// --- Initial cameras -------------------------------------------------------

struct LooseInitOptions {
  // Tree height used when the set-up gives none, in (then arbitrary) world
  // units, > 0. A typical tree height in metres, so that later stages'
  // defaults in world units behave plausibly.
  double assumed_tree_height = 10.0;
  // Focal length of a perspective photo without one (nor a distance), as a
  // multiple of the photo's longer side, > 0. COLMAP's default 1.2 is about
  // 45 degrees across the longer side.
  double default_focal_factor = 1.2;
  // A matte pixel is foreground at or above this alpha, in (0, 1).
  double matte_threshold = 0.5;
  // A matte row belongs to the tree when at least this fraction of its
  // pixels (and at least one) is foreground, in [0, 1): ignores specks.
  double min_row_fraction = 0.002;
  // The base's horizontal position is the foreground centroid of the lowest
  // rows spanning this fraction of the tree's height in the photo, in (0, 1].
  double base_band_fraction = 0.03;
  // Without clicks or a matte, the tree is assumed to stand centred and span
  // this fraction of the photo's height, in (0, 1].
  double fallback_fill = 0.8;
  // Orthographic cameras without a distance are placed this many tree
  // heights from the tree (only where ProjectionCenter() lies), > 0.
  double orthographic_distance_heights = 3.0;

  // Throws InputError ("LooseInit.field must be ...").
  void Check() const;
};

// Where a photo's base and top pixels came from.
enum class LooseAnchorSource { kClicked, kMatte, kGuess };
std::string LooseAnchorSourceName(LooseAnchorSource source);  // "clicked", "matte", "guess"

struct LooseInitView {
  std::string name;
  LooseAnchorSource base_source = LooseAnchorSource::kGuess;
  LooseAnchorSource top_source = LooseAnchorSource::kGuess;
  Eigen::Vector2d base_in_image = Eigen::Vector2d::Zero();  // pixels
  Eigen::Vector2d top_in_image = Eigen::Vector2d::Zero();   // pixels
  // Orthographic: pixels per world unit; perspective: focal length in pixels.
  double scale = 0.0;
  // Perspective: depth of the base along the viewing axis, world units.
  double distance = 0.0;
};

struct LooseInitSummary {
  double tree_height = 0.0;  // world units
  bool height_known = false;
  std::string units;
  std::vector<LooseInitView> views;
  std::vector<std::string> warnings;

  std::string BriefReport() const;
};

// Cameras from the user's angles (see the top of this file). `image_sizes`
// maps every photo name of `setup` to its (width, height) in pixels;
// `mattes` (optional, by photo name; 1 channel, the photo's size) help find
// the base and top where they were not clicked. Views get image ids 1..N and
// camera ids 1..N in the set-up's photo order; cameras are ORTHOGRAPHIC or
// PINHOLE with the principal point at the image centre. Throws InputError
// naming setup.source for a photo without a size, a clicked pixel outside
// its image, a "top" clicked below the "base", or a badly sized matte.
ImageSet InitialLooseCameras(const LooseSetup& setup,
                             const std::map<std::string, Eigen::Vector2i>& image_sizes,
                             const std::map<std::string, FloatImage>& mattes,
                             const LooseInitOptions& options, LooseInitSummary* summary = nullptr);

// --- Refinement ----------------------------------------------------------

struct LooseRefineOptions {
  // Expected error of a click, in pixels (> 0): reprojection residuals are
  // divided by it, which weighs them against the priors.
  double click_sigma_px = 1.0;
  // Scale of the robust losses, in pixels (> 0). The refinement first
  // solves with the Huber loss (errors beyond the scale count linearly; it
  // is convex, so a far-off start still converges), then from there with
  // the Cauchy loss (errors far beyond the scale count logarithmically, so a
  // mis-click barely pulls).
  double robust_loss_px = 3.0;
  // Standard deviations of the priors tying each camera's angles to the
  // user's values, in degrees (> 0). The first photo's azimuth is fixed.
  double azimuth_sigma_deg = 10.0;
  double elevation_sigma_deg = 5.0;
  double roll_sigma_deg = 2.0;
  // Standard deviation of the prior tying log(focal length) to its initial
  // value: for photos with a given focal length, and for photos without one
  // (and for orthographic scales), unitless (> 0).
  double known_focal_sigma = 0.1;
  double unknown_focal_sigma = 0.5;
  // Solver limits.
  int max_iterations = 200;
  // A direction of the unknowns whose singular value, relative to the
  // largest, in the correspondences' (column-normalised) Jacobian is below
  // this is reported as fixed only by the priors, in (0, 1).
  double weak_direction_threshold = 1e-4;

  // Throws InputError ("LooseRefine.field must be ...").
  void Check() const;
};

// How one camera moved.
struct LooseCameraChange {
  std::string name;
  int num_points = 0;                                          // clicked points seen in this photo
  Eigen::Vector3d angles_given_deg = Eigen::Vector3d::Zero();  // the user's
  Eigen::Vector3d angles_initial_deg = Eigen::Vector3d::Zero();  // azimuth, elevation, roll
  Eigen::Vector3d angles_refined_deg = Eigen::Vector3d::Zero();
  // Orthographic scale or focal length: refined / initial - 1.
  double relative_scale_change = 0.0;
  // Movement of the camera centre (perspective) or of the image position of
  // the world origin (orthographic), in world units.
  double translation_change = 0.0;
  double rms_before_px = 0.0, rms_after_px = 0.0;
};

struct LooseRefineSummary {
  bool refined = false;  // false without correspondences (cameras unchanged)
  int num_points = 0;
  int num_observations = 0;
  int num_unknowns = 0;   // free parameters of cameras and points
  int num_equations = 0;  // 2 per observation (priors not counted)
  // Directions of the unknowns the correspondences do not determine (fixed
  // only by the priors); the world's tilt accounts for up to 2 of them.
  int num_weak_directions = 0;
  // Reprojection error over all observations, in pixels, with the best 3D
  // points for the initial cameras (before) and after refinement.
  double rms_before_px = 0.0, rms_after_px = 0.0;
  double max_after_px = 0.0;
  std::string worst_observation;  // "point 'tip3' in photo 'side.jpg'"
  std::vector<LooseCameraChange> cameras;
  std::map<std::string, Eigen::Vector3d> points_in_world;  // refined named points
  std::vector<std::string> warnings;
  std::string termination;  // Ceres' termination type
  int iterations = 0;
  double seconds = 0.0;

  std::string BriefReport() const;
};

struct LooseRefinement {
  ImageSet image_set;
  LooseRefineSummary summary;
};

// Refines `initial` (as made by InitialLooseCameras, or any ImageSet with one
// ORTHOGRAPHIC or PINHOLE (fx = fy) camera per view named as the set-up's
// photos) from the set-up's points. Without points the cameras are returned
// unchanged with a warning. Deterministic (single-threaded solver). Throws
// InputError naming setup.source if a photo has no view or the projections
// disagree.
LooseRefinement RefineLooseCameras(const LooseSetup& setup, const ImageSet& initial,
                                   const LooseRefineOptions& options);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_REGISTRATION_H_
