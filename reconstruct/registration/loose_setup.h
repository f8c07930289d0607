// The description of a loosely registered photo set (thesis 3.3: "we do not
// need an exact registration of these images"): for each of 2-4 photos of a
// tree, roughly where it was taken from (azimuth around the tree, elevation,
// roll), its projection and rough focal length, plus optional named points
// clicked in several photos. Read from a JSON file by ReadLooseSetup
// (loose_setup_io.h), or built in code; turned into cameras by
// InitialLooseCameras and RefineLooseCameras (loose_registration.h).
//
// World frame (sylva's): +Z up, the tree's base at the origin, units those of
// `tree_height` when it is given. Azimuth 0 looks from +X towards the tree,
// azimuth 90 from +Y (counter-clockwise seen from above).
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_H_

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace sylva {

enum class LooseProjection { kOrthographic, kPerspective };

// "orthographic" / "perspective"; ParseLooseProjection throws InputError
// naming `source` for anything else.
std::string LooseProjectionName(LooseProjection projection);
LooseProjection ParseLooseProjection(const std::string& name, const std::string& source);

// One photo and where it was roughly taken from.
struct LoosePhoto {
  std::string name;  // photo path relative to the photo folder
  // Direction the camera looks along, in degrees: azimuth of the camera's
  // position around the tree (finite, any value; 0 = from +X, 90 = from +Y),
  // elevation of the camera above the horizontal, in (-90, 90) (positive:
  // looking down at the tree), and roll about the viewing axis in
  // [-180, 180], positive when the camera is turned clockwise as seen by the
  // photographer (the photo's content then appears turned counter-clockwise).
  double azimuth_deg = 0.0;
  double elevation_deg = 0.0;
  double roll_deg = 0.0;
  LooseProjection projection = LooseProjection::kPerspective;
  // Perspective only, at most one of the two; 0 = unknown. In pixels of the
  // photo, or as a 35-mm-equivalent focal length in mm (36 mm across the
  // photo's longer side).
  double focal_length_px = 0.0;
  double focal_length_35mm = 0.0;
  // Horizontal distance from the camera to the trunk, in the units of
  // LooseSetup::tree_height; 0 = unknown. Perspective photos without a focal
  // length derive it from this; orthographic cameras are placed this far
  // from the tree (their images do not depend on it).
  double distance = 0.0;

  bool HasFocalLength() const { return focal_length_px > 0 || focal_length_35mm > 0; }
  // The focal length in pixels for a photo of width x height; 0 if unknown.
  double FocalLengthPx(int width, int height) const;
};

// Where a point was clicked in one photo.
struct LooseObservation {
  int photo_idx = 0;                                         // index into LooseSetup::photos
  Eigen::Vector2d point_in_image = Eigen::Vector2d::Zero();  // pixels, COLMAP convention
};

// A named 3D point seen in two or more photos.
struct LoosePoint {
  std::string name;
  std::vector<LooseObservation> observations;  // at most one per photo

  // The observation in photo `photo_idx`, or nullptr.
  const LooseObservation* Find(int photo_idx) const;
};

// Names with a meaning. "base" (the foot of the trunk) is the world origin
// and must be among the points whenever points are given; "top" (the tree's
// highest point) sets the scale when the tree height is known.
inline constexpr const char* kLooseBasePoint = "base";
inline constexpr const char* kLooseTopPoint = "top";

struct LooseSetup {
  // Where the set-up came from (the file path), named in every error.
  std::string source = "loose set-up";
  // Height of the tree's highest point (leaves included) above its base, in
  // `units`; 0 = unknown (world units are then arbitrary).
  double tree_height = 0.0;
  std::string units = "arbitrary";
  std::vector<LoosePhoto> photos;  // >= 2
  std::vector<LoosePoint> points;  // may be empty

  // Index of the photo / point with this name, or -1.
  int FindPhoto(const std::string& name) const;
  int FindPoint(const std::string& name) const;
  int NumObservations() const;

  // Checks everything that does not need the images: 2 or more photos with
  // unique non-empty names and valid angles, focal lengths and distances;
  // points with unique names, seen in >= 2 distinct photos, "base" among
  // them if any, finite non-negative pixel positions. Throws InputError
  // naming `source` and the photo or point.
  void Check() const;
  // Checks that every clicked pixel lies inside its photo;
  // image_sizes[i] = (width, height) of photos[i].
  void CheckPixels(const std::vector<Eigen::Vector2i>& image_sizes) const;
};

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_H_
