// The register stage: the photos' cameras in sylva's world frame (up +Z,
// tree base at the origin) -> out/cameras/ (COLMAP text model),
// out/cameras/registration.json and out/cameras/unregistered.txt.
//
// Sources: a given COLMAP model or sylva camera file (taken into the world
// frame), COLMAP's structure from motion on the photos (workspace in
// cache/colmap/), or loose azimuths refined with Ceres (already in the world
// frame).
#include "ui/pipeline/register_stage.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/threading.h"
#include "reconstruct/registration/colmap_runner.h"
#include "reconstruct/registration/loose_registration.h"
#include "reconstruct/registration/loose_setup_io.h"
#include "reconstruct/registration/world_frame.h"

namespace sylva {
namespace {

// COLMAP masks (black = no features) from the mattes: foreground dilated so
// that features on the tree's silhouette edge are kept.
void WriteMasks(const StageContext& context, const fs::path& masks_dir) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  ProgressTask progress(context.progress, "register: writing COLMAP masks");
  ParallelForFirstError(static_cast<int>(names.size()), [&](int i) {
    progress.CheckCancelled();
    const ImageHeader header = ReadImageHeader(project.PhotoPath(names[i]));
    const FloatImage matte = project.LoadMatte(names[i], header.width, header.height);
    const fs::path path = ColmapMaskPath(masks_dir, names[i]);
    fs::create_directories(path.parent_path());
    WriteImage(path, ColmapMaskFromMatte(matte), PixelFormat::kUint8);
  });
}

Json Vector(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json ColmapJson(const ColmapResult& result, const Project& project) {
  return {{"matcher", result.matcher},
          {"single_camera", result.single_camera},
          {"num_models", result.num_models},
          {"mapper_runs", result.mapper_runs},
          {"matching_runs", result.matching_runs},
          {"relaxed_mapping", result.relaxed_mapping},
          {"extraction_seconds", result.extraction_seconds},
          {"matching_seconds", result.matching_seconds},
          {"mapping_seconds", result.mapping_seconds},
          {"colmap_seconds", result.colmap_seconds},
          {"sylva_seconds", result.sylva_seconds},
          {"log", fs::relative(result.log_path, project.root()).generic_string()},
          {"summary", result.BriefReport()}};
}

Json WorldFrameJson(const WorldFrame& frame) {
  const Sim3d& sim = frame.world_from_model;
  return {{"scale", sim.scale},
          {"rotation_wxyz",
           Json::array({sim.rotation.w(), sim.rotation.x(), sim.rotation.y(), sim.rotation.z()})},
          {"translation", Vector(sim.translation)},
          {"up_in_model", Vector(frame.up_in_model)},
          {"base_in_model", Vector(frame.base_in_model)},
          {"tree_height", frame.tree_height},
          {"up_source", frame.up_source},
          {"base_source", frame.base_source},
          {"summary", frame.BriefReport()}};
}

// COLMAP's structure from motion on the photos (model frame).
Registration RegisterWithColmap(const StageContext& context) {
  const Project& project = context.project;
  const fs::path workspace = project.CacheDir() / "colmap";
  fs::path masks_dir;
  if (context.options.colmap.use_masks) {
    masks_dir = workspace / "masks";
    WriteMasks(context, masks_dir);
  }
  const ColmapResult result = RunColmap(project.PhotosDir(), project.photo_names(), masks_dir,
                                        workspace, context.options.colmap, context.progress);
  Registration registration;
  registration.cameras = result.cameras;
  registration.unregistered = result.unregistered;
  registration.units = project.units();
  for (const std::string& note : result.notes) {
    registration.warnings.push_back({"colmap-retry", note});
  }
  registration.details["method"] = "colmap";
  registration.details["colmap"] = ColmapJson(result, project);
  return registration;
}

// The photos of a loose-camera file: their sizes and mattes (each photo
// checked to be in the project's photo folder).
struct LoosePhotos {
  std::map<std::string, Eigen::Vector2i> sizes;
  std::map<std::string, FloatImage> mattes;
  std::vector<Eigen::Vector2i> size_list;  // in the file's order
};

LoosePhotos ReadLoosePhotos(const Project& project, const LooseSetup& setup) {
  LoosePhotos photos;
  for (const LoosePhoto& photo : setup.photos) {
    const fs::path path = project.PhotoPath(photo.name);
    std::error_code ec;
    SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), project.LooseCamerasPath().string())
        << "photo '" << photo.name << "' is not in the project's photo folder";
    const ImageHeader header = ReadImageHeader(path);
    photos.sizes[photo.name] = Eigen::Vector2i(header.width, header.height);
    photos.size_list.push_back(photos.sizes[photo.name]);
    photos.mattes[photo.name] = project.LoadMatte(photo.name, header.width, header.height);
  }
  return photos;
}

// Loose azimuths refined with Ceres (built in the world frame).
Registration RegisterManually(const StageContext& context) {
  const Project& project = context.project;
  const LooseSetup setup = ReadLooseSetup(project.LooseCamerasPath());
  const LoosePhotos photos = ReadLoosePhotos(project, setup);
  setup.CheckPixels(photos.size_list);
  LooseInitSummary init_summary;
  const ImageSet initial = InitialLooseCameras(setup, photos.sizes, photos.mattes,
                                               context.options.loose_init, &init_summary);
  const LooseRefinement refinement =
      RefineLooseCameras(setup, initial, context.options.loose_refine);
  Registration registration;
  for (const std::string& warning : init_summary.warnings) {
    registration.warnings.push_back({"loose-cameras", warning});
  }
  for (const std::string& warning : refinement.summary.warnings) {
    registration.warnings.push_back({"loose-refinement", warning});
  }
  registration.cameras = refinement.image_set;
  registration.in_world_frame = true;
  registration.units = init_summary.height_known ? init_summary.units : project.units();
  registration.details["method"] = "manual";
  registration.details["initial"] = init_summary.BriefReport();
  registration.details["refinement"] = refinement.summary.BriefReport();
  registration.details["rms_before_px"] = refinement.summary.rms_before_px;
  registration.details["rms_after_px"] = refinement.summary.rms_after_px;
  for (const std::string& name : project.photo_names()) {
    if (setup.FindPhoto(name) < 0) registration.unregistered.push_back(name);
  }
  return registration;
}

// The cameras given at init (model frame).
Registration RegisterGiven(const Project& project) {
  Registration registration;
  registration.cameras = project.LoadGivenCameras();
  registration.units = project.units();
  registration.details["method"] = "given";
  return registration;
}

// Takes the cameras into sylva's world frame (up +Z, base at the origin),
// found from the cameras and the mattes.
void TakeIntoWorldFrame(const StageContext& context, Registration* registration) {
  const std::vector<FloatImage> mattes =
      context.LoadMattes(registration->cameras, "register: reading mattes", /*edited=*/false);
  const WorldFrame frame =
      EstimateWorldFrame(registration->cameras, mattes, context.options.world_frame);
  registration->cameras = TransformCameras(registration->cameras, frame);
  registration->in_world_frame = true;
  registration->details["world_frame"] = WorldFrameJson(frame);
  if (context.options.world_frame.known_height > 0) registration->units = frame.units;
}

std::string RegisterBrief(const Registration& registration, int num_photos) {
  std::ostringstream brief;
  brief << registration.cameras.NumViews() << " of " << num_photos << " photos registered ("
        << registration.details["method"].get<std::string>() << ")";
  if (!registration.unregistered.empty()) {
    brief << "; not registered: see out/cameras/unregistered.txt";
  }
  return brief.str();
}

}  // namespace

std::vector<Warning> UnregisteredWarnings(const std::vector<std::string>& unregistered,
                                          const std::vector<std::string>& held_out,
                                          int num_photos) {
  std::vector<Warning> warnings;
  for (const std::string& name : unregistered) {
    if (std::find(held_out.begin(), held_out.end(), name) == held_out.end()) continue;
    warnings.push_back(
        {"held-out-unregistered",
         "held-out photo '" + name + "' was not registered; it is left out of the report", name});
  }
  if (unregistered.empty()) return warnings;
  warnings.push_back(
      {"unregistered-photos",
       std::to_string(unregistered.size()) + " of " + std::to_string(num_photos) +
           " photos not registered (first: " + unregistered.front() +
           "); they are left out of the reconstruction (list in out/cameras/unregistered.txt)",
       ""});
  return warnings;
}

std::vector<fs::path> WriteRegistration(const Registration& registration, const fs::path& dir) {
  // The cameras the later stages read (sylva's camera file holds every
  // model), and the same as a COLMAP text model when COLMAP can hold them
  // (not for orthographic cameras).
  bool colmap_compatible = true;
  for (const auto& [id, camera] : registration.cameras.cameras) {
    colmap_compatible = colmap_compatible && camera.model() != CameraModel::kOrthographic;
  }
  Json details = registration.details;
  details["registered"] = registration.cameras.NumViews();
  details["unregistered"] = registration.unregistered;
  details["units"] = registration.units;
  details["colmap_model"] = colmap_compatible ? "out/cameras/colmap/" : "";
  std::vector<fs::path> written = {dir / "cameras.json", dir / "unregistered.txt",
                                   dir / "registration.json"};
  if (colmap_compatible) {
    WriteColmapModelText(registration.cameras, dir / "colmap");
    for (const char* name : {"cameras.txt", "images.txt", "points3D.txt"}) {
      written.push_back(dir / "colmap" / name);
    }
  } else {
    std::error_code ec;
    fs::remove_all(dir / "colmap", ec);
  }
  std::string list;
  for (const std::string& name : registration.unregistered) list += name + "\n";
  AtomicWriteString(dir / "unregistered.txt", list);
  WriteJsonFile(dir / "registration.json", details);
  WriteCameraFile(dir / "cameras.json", registration.cameras, registration.units);
  return written;
}

StageRun RunRegisterStage(const StageContext& context) {
  const Project& project = context.project;
  StageRun run;
  StepClock clock(&run.profile);
  Registration registration = project.RegistersWithColmap() ? RegisterWithColmap(context)
                              : project.RegistersManually() ? RegisterManually(context)
                                                            : RegisterGiven(project);
  clock.Lap("register");
  if (!registration.in_world_frame) {
    TakeIntoWorldFrame(context, &registration);
    clock.Lap("world_frame");
  }
  const int num_photos = static_cast<int>(project.photo_names().size());
  run.outputs = WriteRegistration(registration, project.RegisteredCamerasDir());
  clock.Lap("write");
  run.warnings = registration.warnings;
  for (const Warning& warning :
       UnregisteredWarnings(registration.unregistered, project.held_out(), num_photos)) {
    run.warnings.push_back(warning);
  }
  run.brief = RegisterBrief(registration, num_photos);
  run.AddFigure("photos", num_photos, "photos");
  run.AddFigure("registered", registration.cameras.NumViews(), "photos");
  run.AddFigure("unregistered", registration.unregistered.size(), "photos");
  return run;
}

}  // namespace sylva
