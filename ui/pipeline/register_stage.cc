// The register stage: the photos' cameras in sylva's world frame (up +Z,
// tree base at the origin) -> out/cameras/ (COLMAP text model),
// out/cameras/registration.json and out/cameras/unregistered.txt.
//
// Sources: a given COLMAP model or sylva camera file (taken into the world
// frame), COLMAP's structure from motion on the photos (workspace in
// cache/colmap/), or loose azimuths refined with Ceres (already in the world
// frame).
#include <chrono>
#include <map>
#include <sstream>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/threading.h"
#include "reconstruct/registration/colmap_runner.h"
#include "reconstruct/registration/loose_registration.h"
#include "reconstruct/registration/loose_setup_io.h"
#include "reconstruct/registration/world_frame.h"
#include "ui/pipeline/stage_context.h"

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

}  // namespace

StageRun RunRegisterStage(const StageContext& context) {
  const Project& project = context.project;
  const PipelineOptions& options = context.options;
  Json details;
  std::string units = project.units();
  ImageSet cameras;
  std::vector<std::string> unregistered;
  std::vector<Warning> notes;  // become the run's warnings
  bool needs_world_frame = true;

  if (project.RegistersWithColmap()) {
    const fs::path workspace = project.CacheDir() / "colmap";
    fs::path masks_dir;
    if (options.colmap.use_masks) {
      masks_dir = workspace / "masks";
      WriteMasks(context, masks_dir);
    }
    const ColmapResult result = RunColmap(project.PhotosDir(), project.photo_names(), masks_dir,
                                          workspace, options.colmap, context.progress);
    cameras = result.cameras;
    unregistered = result.unregistered;
    for (const std::string& note : result.notes) notes.push_back({"colmap-retry", note});
    details["method"] = "colmap";
    details["colmap"] = {{"matcher", result.matcher},
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
  } else if (project.RegistersManually()) {
    const LooseSetup setup = ReadLooseSetup(project.LooseCamerasPath());
    std::map<std::string, Eigen::Vector2i> sizes;
    std::map<std::string, FloatImage> mattes;
    std::vector<Eigen::Vector2i> size_list;
    for (const LoosePhoto& photo : setup.photos) {
      const fs::path path = project.PhotoPath(photo.name);
      std::error_code ec;
      SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), project.LooseCamerasPath().string())
          << "photo '" << photo.name << "' is not in the project's photo folder";
      const ImageHeader header = ReadImageHeader(path);
      sizes[photo.name] = Eigen::Vector2i(header.width, header.height);
      size_list.push_back(sizes[photo.name]);
      mattes[photo.name] = project.LoadMatte(photo.name, header.width, header.height);
    }
    setup.CheckPixels(size_list);
    LooseInitSummary init_summary;
    const ImageSet initial =
        InitialLooseCameras(setup, sizes, mattes, options.loose_init, &init_summary);
    const LooseRefinement refinement = RefineLooseCameras(setup, initial, options.loose_refine);
    for (const std::string& warning : init_summary.warnings) {
      notes.push_back({"loose-cameras", warning});
    }
    for (const std::string& warning : refinement.summary.warnings) {
      notes.push_back({"loose-refinement", warning});
    }
    cameras = refinement.image_set;
    details["method"] = "manual";
    details["initial"] = init_summary.BriefReport();
    details["refinement"] = refinement.summary.BriefReport();
    details["rms_before_px"] = refinement.summary.rms_before_px;
    details["rms_after_px"] = refinement.summary.rms_after_px;
    if (init_summary.height_known) units = init_summary.units;
    needs_world_frame = false;  // built in the world frame
    for (const std::string& name : project.photo_names()) {
      if (setup.FindPhoto(name) < 0) unregistered.push_back(name);
    }
  } else {
    cameras = project.LoadGivenCameras();
    details["method"] = "given";
  }

  if (needs_world_frame) {
    const std::vector<FloatImage> mattes = context.LoadMattes(cameras, "register: reading mattes");
    const WorldFrame frame = EstimateWorldFrame(cameras, mattes, options.world_frame);
    cameras = TransformCameras(cameras, frame);
    const Sim3d& sim = frame.world_from_model;
    details["world_frame"] = {{"scale", sim.scale},
                              {"rotation_wxyz", Json::array({sim.rotation.w(), sim.rotation.x(),
                                                             sim.rotation.y(), sim.rotation.z()})},
                              {"translation", Vector(sim.translation)},
                              {"up_in_model", Vector(frame.up_in_model)},
                              {"base_in_model", Vector(frame.base_in_model)},
                              {"tree_height", frame.tree_height},
                              {"up_source", frame.up_source},
                              {"base_source", frame.base_source},
                              {"summary", frame.BriefReport()}};
    if (options.world_frame.known_height > 0) units = frame.units;
  }
  for (const std::string& name : unregistered) {
    if (project.IsHeldOut(name)) {
      notes.push_back(
          {"held-out-unregistered",
           "held-out photo '" + name + "' was not registered; it is left out of the report", name});
    }
  }
  details["registered"] = cameras.NumViews();
  details["unregistered"] = unregistered;
  details["units"] = units;

  // The cameras the later stages read (sylva's camera file holds every
  // model), and the same as a COLMAP text model when COLMAP can hold them
  // (not for orthographic cameras).
  const fs::path dir = project.RegisteredCamerasDir();
  bool colmap_compatible = true;
  for (const auto& [id, camera] : cameras.cameras) {
    colmap_compatible = colmap_compatible && camera.model() != CameraModel::kOrthographic;
  }
  details["colmap_model"] = colmap_compatible ? "out/cameras/colmap/" : "";
  std::string list;
  for (const std::string& name : unregistered) list += name + "\n";
  StageRun run;
  run.outputs = {dir / "cameras.json", dir / "unregistered.txt", dir / "registration.json"};
  if (colmap_compatible) {
    WriteColmapModelText(cameras, dir / "colmap");
    for (const char* name : {"cameras.txt", "images.txt", "points3D.txt"}) {
      run.outputs.push_back(dir / "colmap" / name);
    }
  } else {
    std::error_code ec;
    fs::remove_all(dir / "colmap", ec);
  }
  AtomicWriteString(dir / "unregistered.txt", list);
  WriteJsonFile(dir / "registration.json", details);
  WriteCameraFile(dir / "cameras.json", cameras, units);

  run.warnings = notes;
  if (!unregistered.empty()) {
    run.warnings.push_back(
        {"unregistered-photos",
         std::to_string(unregistered.size()) + " of " +
             std::to_string(project.photo_names().size()) +
             " photos not registered (first: " + unregistered.front() +
             "); they are left out of the reconstruction (list in out/cameras/unregistered.txt)",
         ""});
  }
  std::ostringstream brief;
  brief << cameras.NumViews() << " of " << project.photo_names().size() << " photos registered ("
        << details["method"].get<std::string>() << ")";
  if (!unregistered.empty()) brief << "; not registered: see out/cameras/unregistered.txt";
  run.brief = brief.str();
  return run;
}

}  // namespace sylva
