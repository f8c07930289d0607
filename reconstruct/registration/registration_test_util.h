// Test and benchmark support for registration: comparing two registrations
// of the same photos, and the simple mattes of ROMI's photos (black velvet).
// Not part of sylva_reconstruct; compiled into the tests and benchmarks.
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_REGISTRATION_TEST_UTIL_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_REGISTRATION_TEST_UTIL_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry/sim3.h"
#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/statistics.h"  // Median

namespace sylva {

// Per-view errors of `estimate` against `truth` (matched by photo name) after
// the similarity that best maps the estimated camera centres onto the true
// ones: rotation error in degrees, centre error in `truth`'s units. Views of
// `estimate` missing from `truth` throw Error; at least 3 views are needed.
struct PoseErrors {
  Sim3d truth_from_estimate;
  std::vector<double> rotation_degrees;
  std::vector<double> position;
};
PoseErrors ComparePoses(const ImageSet& estimate, const ImageSet& truth);

double Max(const std::vector<double>& values);

// The file names in `folder` (not recursive), sorted.
std::vector<std::string> SortedFileNames(const std::filesystem::path& folder);

// ROMI real_plant's matte rule (its PROVENANCE.md): foreground where
// min(R, G, B) > 95/255 and the pixel is not orange (R - B <= 60/255); a
// binary one-channel image. The plant, pot and metal rod pass; the velvet and
// orange markers do not.
FloatImage RomiMatte(const FloatImage& photo);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_REGISTRATION_TEST_UTIL_H_
