// The register stage's steps that a test can call with data built in code
// (RunRegisterStage, in stage_context.h, chains them): each camera source
// gives a Registration, taken into the world frame when it is not already,
// then written to out/cameras/.
#ifndef SYLVA_UI_PIPELINE_REGISTER_STAGE_H_
#define SYLVA_UI_PIPELINE_REGISTER_STAGE_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/json_util.h"
#include "core/types/image_set.h"
#include "core/util/warning.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {

// What one camera source found.
struct Registration {
  ImageSet cameras;
  // The project's photos that have no camera (in the project's order).
  std::vector<std::string> unregistered;
  // What went wrong on the way without stopping the registration (a COLMAP
  // retry, a loose camera the refinement could not place well).
  std::vector<Warning> warnings;
  // The source's own figures for out/cameras/registration.json ("method"
  // and, by method, "colmap", "initial", "refinement", "world_frame", ...).
  Json details;
  // World units of `cameras`: the project's, unless the source measured the
  // scale (a loose-camera file's height, WorldFrame.known_height).
  std::string units;
  // False for cameras still in the source's own frame (a COLMAP model).
  bool in_world_frame = false;
};

// The warnings about photos without a camera: each held-out one by name
// (the report will be a view short), then one for them all. `num_photos`:
// the project's photo count.
std::vector<Warning> UnregisteredWarnings(const std::vector<std::string>& unregistered,
                                          const std::vector<std::string>& held_out, int num_photos);

// Writes `dir`/cameras.json, unregistered.txt, registration.json (the
// details with the counts and units) and, unless a camera is orthographic
// (COLMAP has no such model), the COLMAP text model `dir`/colmap/ (else
// removes it); returns the files written.
std::vector<std::filesystem::path> WriteRegistration(const Registration& registration,
                                                     const std::filesystem::path& dir);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_REGISTER_STAGE_H_
