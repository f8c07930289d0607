// The sylva camera file: a small JSON description of registered views, for
// cases COLMAP cannot express (orthographic views, hand-placed cameras).
//
// {
//   "format": "sylva-cameras", "version": 1,
//   "units": "arbitrary",                      // or "m", "mm", ...
//   "cameras": [
//     {"camera_id": 1, "model": "ORTHOGRAPHIC", "width": 512, "height": 512,
//      "params": [100, 100, 256, 256]}         // COLMAP order, see camera.h
//   ],
//   "images": [
//     {"image_id": 1, "name": "front.png", "camera_id": 1,
//      "cam_from_world": {"qvec": [1, 0, 0, 0], "tvec": [0, 0, 5]}},   // COLMAP's QW QX QY QZ
//     {"image_id": 2, "name": "side.png", "camera_id": 1,
//      "look_at": {"center": [5, 0, 1], "target": [0, 0, 1], "up": [0, 0, 1]}}
//   ]
// }
// An image gives its pose either as cam_from_world (x_cam = R x_world + t) or
// as look_at (camera centre, a point it looks at, and the world up direction).
#ifndef SYLVA_CORE_IO_CAMERA_FILE_H_
#define SYLVA_CORE_IO_CAMERA_FILE_H_

#include <filesystem>
#include <string>

#include "core/types/image_set.h"

namespace sylva {

// Throws InputError naming the file and the JSON location of any problem.
ImageSet ReadCameraFile(const std::filesystem::path& path, std::string* units = nullptr);

// Writes atomically (poses as cam_from_world).
void WriteCameraFile(const std::filesystem::path& path, const ImageSet& image_set,
                     const std::string& units = "arbitrary");

}  // namespace sylva

#endif  // SYLVA_CORE_IO_CAMERA_FILE_H_
