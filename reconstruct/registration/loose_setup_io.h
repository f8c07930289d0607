// The loose-camera file: a hand-written JSON description of 2-4 photos of a
// tree for manual ("loose") registration, when structure from motion fails.
//
// {
//   "format": "sylva-loose-cameras", "version": 1,     // optional, checked if given
//   "tree_height": 6.5, "units": "m",                  // optional; see below
//   "photos": [
//     {"name": "front.jpg", "azimuth_deg": 0, "projection": "perspective",
//      "focal_length_35mm": 28, "elevation_deg": 5},
//     {"name": "side.jpg", "azimuth_deg": 90, "projection": "perspective",
//      "focal_length_px": 3100, "distance": 15, "roll_deg": -2}
//   ],
//   "points": [                                        // optional
//     {"name": "base", "seen": {"front.jpg": [1510, 2950], "side.jpg": [1490, 2962]}},
//     {"name": "top",  "seen": {"front.jpg": [1480, 400],  "side.jpg": [1530, 377]}},
//     {"name": "tip1", "seen": {"front.jpg": [620, 1210],  "side.jpg": [1700, 1190]}}
//   ]
// }
//
// Photos (2 or more; the first one's azimuth is kept exactly, it orients the
// world about the vertical axis):
//   name               photo path relative to the photo folder (required)
//   azimuth_deg        where the photo was taken from, around the tree, in
//                      degrees (required): 0 = from +X, 90 = from +Y, ...
//   projection         "orthographic" or "perspective" (required)
//   elevation_deg      camera above the horizontal, looking down, in
//                      (-90, 90); default 0
//   roll_deg           camera turned clockwise about its viewing axis as seen
//                      by the photographer, in [-180, 180]; default 0
//   focal_length_px    perspective only: rough focal length in pixels, or
//   focal_length_35mm  as a 35-mm-equivalent focal length in mm (36 mm across
//                      the longer image side; phones show it in EXIF/the app).
//                      Unknown: 1.2 x the longer side (~45 degrees across it,
//                      COLMAP's default), see LooseInitOptions.
//   distance           horizontal distance from the camera to the trunk, in
//                      tree_height's units; optional
// Points (optional; if given, "base" must be one of them):
//   name               unique; "base" = foot of the trunk (world origin),
//                      "top" = the tree's highest point (sets the scale with
//                      tree_height); any other name is a free 3D point
//                      (a branch tip, a fork, a bird box)
//   seen               {photo name: [x, y]} for 2 or more photos; pixel
//                      position with x right, y down, (0, 0) the image's top
//                      left corner and pixel centres at +0.5 (COLMAP's
//                      convention; an image viewer's integer pixel index is
//                      within half a pixel)
// tree_height: height of the tree's highest point above its base (> 0);
// units: a free label for it ("m"); without tree_height units are arbitrary.
// Unknown keys are refused (they are usually misspelt ones).
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_IO_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_IO_H_

#include <filesystem>
#include <string>

#include "reconstruct/registration/loose_setup.h"

namespace sylva {

// Reads and validates (LooseSetup::Check) a loose-camera file. Throws
// InputError naming the file, the JSON location and the photo or point.
// Pixel positions are checked against the image sizes later, by
// InitialLooseCameras.
LooseSetup ReadLooseSetup(const std::filesystem::path& path);

// The same from JSON text; `source` names it in errors.
LooseSetup ParseLooseSetup(const std::string& text, const std::string& source);

// Writes `setup` in the format above (atomically), e.g. as a template for a
// user to fill in.
void WriteLooseSetup(const std::filesystem::path& path, const LooseSetup& setup);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_LOOSE_SETUP_IO_H_
