#include "ui/pipeline/project.h"

#include <unistd.h>

#include <algorithm>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/threading.h"

namespace sylva {
namespace {

constexpr char kFormatName[] = "sylva-project";
constexpr int kFormatVersion = 1;
// A matte with no pixel above this alpha is empty.
constexpr float kEmptyMatteAlpha = 1.0f / 255.0f;

ImageSet ReadCameraSource(const std::string& type, const fs::path& path, std::string* units) {
  if (type == "colmap") {
    SYLVA_CHECK_INPUT(IsColmapModelDir(path), path.string())
        << "not a COLMAP model folder (no cameras.txt or cameras.bin)";
    return ReadColmapModel(path);
  }
  return ReadCameraFile(path, units);
}

// Checks a view's photo (and matte) exist, decode and match its camera's
// size, and that the matte is not empty. Everything is decoded in full, so a
// truncated file is refused here rather than after minutes of work.
void CheckViewFiles(const Project& project, const ImageSet& image_set, int view_idx,
                    bool mattes_from_photos) {
  const View& view = image_set.views[view_idx];
  const Camera& camera = image_set.CameraOf(view);
  const fs::path photo = project.PhotoPath(view.name);
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(photo, ec), photo.string())
      << "photo '" << view.name << "' named by the camera model is missing";
  const ImageHeader header = ReadImageHeader(photo);
  SYLVA_CHECK_INPUT(header.width == camera.width() && header.height == camera.height(),
                    photo.string())
      << "photo is " << header.width << "x" << header.height << " but its camera is "
      << camera.width() << "x" << camera.height();
  if (mattes_from_photos) {
    SYLVA_CHECK_INPUT(header.alpha_channel >= 0, photo.string())
        << "photo has no alpha channel and no matte folder was given (use --mattes DIR)";
  } else {
    ReadImage(photo);  // LoadMatte decodes it when the photo is the matte
  }
  project.LoadMatte(image_set, view_idx);
}

// Copies the files of a COLMAP model (and nothing else from its folder).
void CopyColmapModel(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  std::error_code ec;
  for (const char* name : {"cameras", "images", "points3D"}) {
    for (const char* ext : {".txt", ".bin"}) {
      const fs::path file = from / (std::string(name) + ext);
      if (fs::is_regular_file(file, ec)) fs::copy_file(file, to / file.filename());
    }
  }
}

// Copies the photos and mattes the model names (keeping sub-folders).
void CopyViewFiles(const ImageSet& image_set, const fs::path& photos_dir,
                   const fs::path& mattes_dir, const fs::path& project_root) {
  for (const View& view : image_set.views) {
    const fs::path target = project_root / "photos" / view.name;
    fs::create_directories(target.parent_path());
    fs::copy_file(photos_dir / view.name, target, fs::copy_options::overwrite_existing);
    if (mattes_dir.empty()) continue;
    const fs::path matte = FindMatteFile(mattes_dir, view.name);
    const fs::path matte_target = project_root / "mattes" / fs::relative(matte, mattes_dir);
    fs::create_directories(matte_target.parent_path());
    fs::copy_file(matte, matte_target, fs::copy_options::overwrite_existing);
  }
}

std::string AbsoluteString(const fs::path& path) {
  return fs::weakly_canonical(fs::absolute(path)).string();
}

}  // namespace

bool Project::IsHeldOut(const std::string& view_name) const {
  return std::find(held_out_.begin(), held_out_.end(), view_name) != held_out_.end();
}

fs::path Project::Resolve(const std::string& path) const {
  const fs::path p(path);
  return p.is_absolute() ? p : root_ / p;
}

fs::path Project::PhotoPath(const std::string& view_name) const {
  return Resolve(photos_) / view_name;
}

fs::path Project::MattePath(const std::string& view_name) const {
  if (mattes_.empty()) return PhotoPath(view_name);
  return FindMatteFile(Resolve(mattes_), view_name);
}

std::vector<fs::path> Project::CameraFiles() const {
  const fs::path path = Resolve(camera_path_);
  if (camera_type_ != "colmap") return {path};
  std::vector<fs::path> files;
  for (const char* name : {"cameras", "images", "points3D"}) {
    for (const char* ext : {".txt", ".bin"}) files.push_back(path / (std::string(name) + ext));
  }
  return files;
}

ImageSet Project::LoadCameras() const {
  ImageSet image_set = ReadCameraSource(camera_type_, Resolve(camera_path_), nullptr);
  for (const std::string& name : held_out_) {
    SYLVA_CHECK_INPUT(image_set.FindView(name) >= 0, SettingsPath().string())
        << "held-out view '" << name << "' is not in the camera model";
  }
  return image_set;
}

FloatImage Project::LoadMatte(const ImageSet& image_set, int view_idx) const {
  const View& view = image_set.views.at(view_idx);
  const fs::path path = MattePath(view.name);
  SYLVA_CHECK_INPUT(!path.empty(), (Resolve(mattes_) / view.name).string())
      << "no matte for photo '" << view.name
      << "' in the matte folder (same relative name, any image extension)";
  FloatImage matte = ReadMatte(path);
  const Camera& camera = image_set.CameraOf(view);
  SYLVA_CHECK_INPUT(matte.width() == camera.width() && matte.height() == camera.height(),
                    path.string())
      << "matte is " << matte.width() << "x" << matte.height() << " but the camera is "
      << camera.width() << "x" << camera.height();
  const bool has_foreground = std::any_of(matte.values().begin(), matte.values().end(),
                                          [](float a) { return a > kEmptyMatteAlpha; });
  SYLVA_CHECK_INPUT(has_foreground, path.string()) << "matte is empty (no foreground pixels)";
  return matte;
}

void Project::ApplySavedOptions(OptionRegistry* registry) const {
  registry->SetFromJson(ParseJson(options_json_, SettingsPath().string()),
                        SettingsPath().string());
}

void Project::SaveOptions(const OptionRegistry& registry) {
  options_json_ = registry.ToJson(/*only_changed=*/true).dump();
  Write();
}

void Project::Write() const {
  Json json;
  json["format"] = kFormatName;
  json["version"] = kFormatVersion;
  json["photos"] = photos_;
  json["mattes"] = mattes_;
  json["cameras"] = {{"type", camera_type_}, {"path", camera_path_}};
  json["units"] = units_;
  json["held_out"] = held_out_;
  json["options"] = ParseJson(options_json_, SettingsPath().string());
  WriteJsonFile(SettingsPath(), json);
}

Project Project::Open(const fs::path& root) {
  Project project;
  project.root_ = root;
  const fs::path settings = project.SettingsPath();
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(settings, ec), settings.string())
      << "not a sylva project (no sylva.json); create one with 'sylva init'";
  const Json json = ReadJsonFile(settings);
  const JsonCursor root_json(json, settings.string());
  if (root_json["format"].AsString() != kFormatName) root_json["format"].Fail("not a sylva project");
  if (root_json["version"].AsInt() != kFormatVersion) root_json["version"].Fail("unsupported version");
  project.photos_ = root_json["photos"].AsString();
  project.mattes_ = root_json["mattes"].AsString();
  project.camera_type_ = root_json["cameras"]["type"].AsString();
  if (project.camera_type_ != "colmap" && project.camera_type_ != "sylva") {
    root_json["cameras"]["type"].Fail("expected 'colmap' or 'sylva'");
  }
  project.camera_path_ = root_json["cameras"]["path"].AsString();
  project.units_ = root_json["units"].AsString();
  const JsonCursor held_out = root_json["held_out"];
  for (size_t i = 0; i < held_out.Size(); ++i) project.held_out_.push_back(held_out[i].AsString());
  if (root_json.Has("options")) {
    if (!root_json["options"].IsObject()) root_json["options"].Fail("expected an object");
    project.options_json_ = root_json["options"].value().dump();
  }
  return project;
}

Project Project::Create(const ProjectSetup& setup) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(setup.root, ec), setup.root.string())
      << "already exists; choose a new project folder";
  SYLVA_CHECK_INPUT(fs::is_directory(setup.photos_dir, ec), setup.photos_dir.string())
      << "photo folder not found";
  SYLVA_CHECK_INPUT(setup.mattes_dir.empty() || fs::is_directory(setup.mattes_dir, ec),
                    setup.mattes_dir.string())
      << "matte folder not found";
  const bool colmap = !setup.colmap_model_dir.empty();
  SYLVA_CHECK_INPUT(colmap != !setup.camera_file.empty(), "init")
      << "give exactly one of --colmap MODEL_DIR and --cameras FILE.json";

  // Build the project in a temporary folder beside the target, then rename.
  const fs::path root = fs::absolute(setup.root);
  const fs::path staging = TempPathBeside(root);
  fs::create_directories(staging);
  try {
    Project project;
    project.root_ = staging;
    project.camera_type_ = colmap ? "colmap" : "sylva";
    project.held_out_ = setup.held_out;
    std::string file_units;
    const ImageSet image_set = ReadCameraSource(
        project.camera_type_, colmap ? setup.colmap_model_dir : setup.camera_file, &file_units);
    project.units_ = !setup.units.empty() ? setup.units
                                          : (file_units.empty() ? "arbitrary" : file_units);
    project.photos_ = AbsoluteString(setup.photos_dir);
    project.mattes_ = setup.mattes_dir.empty() ? "" : AbsoluteString(setup.mattes_dir);
    // Every photo and matte is decoded (a truncated file is caught now, not
    // half-way through a run); in parallel, with the first view's error shown.
    ParallelForFirstError(image_set.NumViews(), [&](int v) {
      CheckViewFiles(project, image_set, v, setup.mattes_dir.empty());
    });
    for (const std::string& name : setup.held_out) {
      SYLVA_CHECK_INPUT(image_set.FindView(name) >= 0, "--held-out")
          << "view '" << name << "' is not in the camera model";
    }
    SYLVA_CHECK_INPUT(image_set.NumViews() > static_cast<int>(setup.held_out.size()), "--held-out")
        << "every view is held out; at least one must remain for the reconstruction";

    if (colmap) {
      CopyColmapModel(setup.colmap_model_dir, staging / "cameras" / "colmap");
      project.camera_path_ = "cameras/colmap";
    } else {
      fs::create_directories(staging / "cameras");
      fs::copy_file(setup.camera_file, staging / "cameras" / "cameras.json");
      project.camera_path_ = "cameras/cameras.json";
    }
    if (setup.copy_inputs) {
      CopyViewFiles(image_set, setup.photos_dir, setup.mattes_dir, staging);
      project.photos_ = "photos";
      project.mattes_ = setup.mattes_dir.empty() ? "" : "mattes";
    }
    fs::create_directories(staging / "edits");
    project.Write();
    fs::rename(staging, root);
    project.root_ = root;
    return project;
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
}

}  // namespace sylva
