#include "ui/pipeline/project.h"

#include <unistd.h>

#include <algorithm>
#include <sstream>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/threading.h"
#include "reconstruct/density/density_edits.h"
#include "reconstruct/registration/loose_setup_io.h"
#include "sketch/drawing_io.h"
#include "sketch/sketch_views.h"

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

// Checks a photo exists and decodes in full (a truncated file is refused
// here rather than after minutes of work), with the camera's size when there
// is one, and that its matte (given or the alpha channel) is valid.
void CheckPhotoFiles(const Project& project, const std::string& name, const Camera* camera) {
  const fs::path photo = project.PhotoPath(name);
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(photo, ec), photo.string())
      << "photo '" << name << "' is missing";
  const ImageHeader header = ReadImageHeader(photo);
  if (camera != nullptr) {
    SYLVA_CHECK_INPUT(header.width == camera->width() && header.height == camera->height(),
                      photo.string())
        << "photo is " << header.width << "x" << header.height << " but its camera is "
        << camera->width() << "x" << camera->height();
  }
  SYLVA_CHECK_INPUT(header.channels >= 3 || !project.ComputesMattes(), photo.string())
      << "photo has " << header.channels << " channel(s); matting needs colour photos";
  if (project.ComputesMattes()) {
    ReadImage(photo);
    return;
  }
  if (project.MattePath(name) != photo) ReadImage(photo);  // else LoadMatte decodes it
  project.LoadMatte(name, header.width, header.height);
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

// Copies the photos and mattes (keeping sub-folders).
void CopyViewFiles(const std::vector<std::string>& names, const fs::path& photos_dir,
                   const fs::path& mattes_dir, const fs::path& project_root) {
  for (const std::string& name : names) {
    const fs::path target = project_root / "photos" / name;
    fs::create_directories(target.parent_path());
    fs::copy_file(photos_dir / name, target, fs::copy_options::overwrite_existing);
    if (mattes_dir.empty()) continue;
    const fs::path matte = FindMatteFile(mattes_dir, name);
    const fs::path matte_target = project_root / "mattes" / fs::relative(matte, mattes_dir);
    fs::create_directories(matte_target.parent_path());
    fs::copy_file(matte, matte_target, fs::copy_options::overwrite_existing);
  }
}

std::string AbsoluteString(const fs::path& path) {
  return fs::weakly_canonical(fs::absolute(path)).string();
}

// The checks of `sylva init`'s arguments that need no photo: a new project
// folder, existing input folders, exactly one camera source.
void CheckSetup(const ProjectSetup& setup) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(!fs::exists(setup.root, ec), setup.root.string())
      << "already exists; choose a new project folder";
  SYLVA_CHECK_INPUT(fs::is_directory(setup.photos_dir, ec), setup.photos_dir.string())
      << "photo folder not found";
  SYLVA_CHECK_INPUT(setup.mattes_dir.empty() || fs::is_directory(setup.mattes_dir, ec),
                    setup.mattes_dir.string())
      << "matte folder not found";
  const int num_sources =
      !setup.colmap_model_dir.empty() + !setup.camera_file.empty() + !setup.register_method.empty();
  SYLVA_CHECK_INPUT(num_sources == 1, "init")
      << "give exactly one of --colmap MODEL_DIR, --cameras FILE.json and --register "
         "colmap|manual";
  SYLVA_CHECK_INPUT(setup.register_method.empty() || setup.register_method == "colmap" ||
                        setup.register_method == "manual",
                    "--register")
      << "expected 'colmap' or 'manual', got '" << setup.register_method << "'";
  const bool manual = setup.register_method == "manual";
  SYLVA_CHECK_INPUT(manual == !setup.loose_cameras_file.empty(), "--loose-cameras")
      << (manual ? "--register manual needs --loose-cameras FILE.json (azimuths per photo)"
                 : "--loose-cameras is only used with --register manual");
  if (manual) {
    SYLVA_CHECK_INPUT(fs::is_regular_file(setup.loose_cameras_file, ec),
                      setup.loose_cameras_file.string())
        << "loose-camera file not found";
  }
}

// The project's photos and where their cameras come from.
struct PhotoList {
  std::string camera_type;         // "colmap", "sylva", "manual" or "sfm"
  std::vector<std::string> names;  // sorted
  ImageSet given;                  // the given cameras (none when registering)
  std::string file_units;          // the camera file's units ("" if none)
};

// The photos of the given camera model, or (registering) of the photo folder.
PhotoList ReadPhotoList(const ProjectSetup& setup) {
  PhotoList photos;
  if (!setup.colmap_model_dir.empty() || !setup.camera_file.empty()) {
    photos.camera_type = !setup.colmap_model_dir.empty() ? "colmap" : "sylva";
    photos.given = ReadCameraSource(
        photos.camera_type,
        photos.camera_type == "colmap" ? setup.colmap_model_dir : setup.camera_file,
        &photos.file_units);
    for (const View& view : photos.given.views) photos.names.push_back(view.name);
    std::sort(photos.names.begin(), photos.names.end());
    return photos;
  }
  photos.camera_type = setup.register_method == "manual" ? "manual" : "sfm";
  photos.names = ListImageFiles(setup.photos_dir);
  SYLVA_CHECK_INPUT(photos.names.size() >= 2, setup.photos_dir.string())
      << "registration needs at least 2 photos; found " << photos.names.size();
  return photos;
}

// Refuses two photos whose computed mattes would share a file (a.jpg, a.png).
void CheckMatteNamesDiffer(const std::vector<std::string>& photo_names,
                           const fs::path& photos_dir) {
  std::vector<std::string> matte_names;
  for (const std::string& name : photo_names) {
    matte_names.push_back(fs::path(name).replace_extension().generic_string());
  }
  std::sort(matte_names.begin(), matte_names.end());
  const auto duplicate = std::adjacent_find(matte_names.begin(), matte_names.end());
  SYLVA_CHECK_INPUT(duplicate == matte_names.end(), photos_dir.string())
      << "two photos are named '" << *duplicate
      << ".*' with different extensions; rename one (their mattes would clash)";
}

// The matte source: a folder ("given"), the photos' alpha channels ("alpha",
// all or none must have one), or "computed".
std::string FindMatteSource(const Project& project, const ProjectSetup& setup) {
  if (!setup.mattes_dir.empty()) return "given";
  int with_alpha = 0;
  fs::path without_alpha;  // the first photo without an alpha channel
  for (const std::string& name : project.photo_names()) {
    const fs::path photo = project.PhotoPath(name);
    std::error_code ec;
    SYLVA_CHECK_INPUT(fs::is_regular_file(photo, ec), photo.string())
        << "photo '" << name << "' named by the camera model is missing";
    const bool has_alpha = ReadImageHeader(photo).alpha_channel >= 0;
    with_alpha += has_alpha;
    if (!has_alpha && without_alpha.empty()) without_alpha = photo;
  }
  SYLVA_CHECK_INPUT(with_alpha == 0 || without_alpha.empty(), without_alpha.string())
      << "photo has no alpha channel while others have one; give --mattes DIR, or "
         "photos without alpha so that sylva computes the mattes";
  return with_alpha == 0 ? "computed" : "alpha";
}

// Every photo and matte is decoded (a truncated file is caught now, not
// half-way through a run); in parallel, with the first photo's error shown.
void CheckInputFiles(const Project& project, const ImageSet& given) {
  ParallelForFirstError(static_cast<int>(project.photo_names().size()), [&](int i) {
    const std::string& name = project.photo_names()[i];
    const int v = given.FindView(name);
    CheckPhotoFiles(project, name, v >= 0 ? &given.CameraOf(v) : nullptr);
  });
}

// Each held-out view is a photo of the project, and at least one is not.
void CheckHeldOut(const std::vector<std::string>& photo_names,
                  const std::vector<std::string>& held_out) {
  for (const std::string& name : held_out) {
    SYLVA_CHECK_INPUT(std::binary_search(photo_names.begin(), photo_names.end(), name),
                      "--held-out")
        << "view '" << name << "' is not one of the project's photos";
  }
  SYLVA_CHECK_INPUT(photo_names.size() > held_out.size(), "--held-out")
      << "every view is held out; at least one must remain for the reconstruction";
}

// Each prior view is a photo of the project and not held out.
void CheckPriorViews(const std::vector<std::string>& photo_names,
                     const std::vector<std::string>& held_out,
                     const std::vector<std::string>& prior_views) {
  for (const std::string& name : prior_views) {
    SYLVA_CHECK_INPUT(std::binary_search(photo_names.begin(), photo_names.end(), name),
                      "prior views")
        << "view '" << name << "' is not one of the project's photos";
    SYLVA_CHECK_INPUT(std::find(held_out.begin(), held_out.end(), name) == held_out.end(),
                      "prior views")
        << "view '" << name << "' is held out; a prior view is an input";
  }
}

// The loose-camera file must name photos of the folder.
void CheckLoosePhotos(const ProjectSetup& setup, const std::vector<std::string>& photo_names) {
  const LooseSetup loose = ReadLooseSetup(setup.loose_cameras_file);
  for (const LoosePhoto& photo : loose.photos) {
    SYLVA_CHECK_INPUT(std::binary_search(photo_names.begin(), photo_names.end(), photo.name),
                      setup.loose_cameras_file.string())
        << "photo '" << photo.name << "' is not in the photo folder " << setup.photos_dir.string();
  }
}

// Copies the camera source into `project_root`/cameras/; returns its path
// relative to the project ("" for "sfm": COLMAP registers the photos).
std::string CopyCameraSource(const ProjectSetup& setup, const std::string& camera_type,
                             const fs::path& project_root) {
  if (camera_type == "colmap") {
    CopyColmapModel(setup.colmap_model_dir, project_root / "cameras" / "colmap");
    return "cameras/colmap";
  }
  if (camera_type == "sylva") {
    fs::create_directories(project_root / "cameras");
    fs::copy_file(setup.camera_file, project_root / "cameras" / "cameras.json");
    return "cameras/cameras.json";
  }
  if (camera_type == "manual") {
    fs::create_directories(project_root / "cameras");
    fs::copy_file(setup.loose_cameras_file, project_root / "cameras" / "loose.json");
    return "cameras/loose.json";
  }
  return "";
}

}  // namespace

std::vector<std::string> ParseViewNames(const std::string& value) {
  std::vector<std::string> names;
  std::string text = value;
  if (!value.empty() && value[0] == '@') text = ReadFileToString(value.substr(1));
  std::string name;
  std::istringstream stream(text);
  const char separator = (!value.empty() && value[0] == '@') ? '\n' : ',';
  while (std::getline(stream, name, separator)) {
    const size_t begin = name.find_first_not_of(" \t\r");
    if (begin == std::string::npos) continue;
    names.push_back(name.substr(begin, name.find_last_not_of(" \t\r") - begin + 1));
  }
  return names;
}

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

fs::path Project::PhotosDir() const { return Resolve(photos_); }

fs::path Project::MattePath(const std::string& view_name) const {
  if (matte_source_ == "computed") return ComputedMattePath(view_name);
  if (matte_source_ == "alpha") return PhotoPath(view_name);
  return FindMatteFile(Resolve(mattes_), view_name);
}

fs::path Project::ComputedMattePath(const std::string& view_name) const {
  return OutDir() / "mattes" / fs::path(view_name).replace_extension(".png");
}

fs::path Project::TrimapHintPath(const std::string& view_name) const {
  return FindMatteFile(EditsDir() / "trimaps", view_name);
}

fs::path Project::AttractorGraphPath(const std::string& view_name) const {
  return OutDir() / "attractors" / fs::path(view_name).replace_extension(".json");
}

fs::path Project::AttractorOverlayPath(const std::string& view_name) const {
  return OutDir() / "attractors" / fs::path(view_name).replace_extension(".png");
}

namespace {

// edits/<name without extension><suffix> if it is a file, else empty.
fs::path ExistingEdit(const fs::path& edits_dir, const std::string& view_name, const char* suffix) {
  fs::path path = edits_dir / fs::path(view_name).replace_extension();
  path += suffix;
  std::error_code ec;
  return fs::is_regular_file(path, ec) ? path : fs::path();
}

}  // namespace

fs::path Project::AttractorEditPath(const std::string& view_name) const {
  return ExistingEdit(EditsDir(), view_name, ".attractors.json");
}

fs::path Project::StrokesPath(const std::string& view_name) const {
  const fs::path svg = ExistingEdit(EditsDir(), view_name, ".strokes.svg");
  return svg.empty() ? ExistingEdit(EditsDir(), view_name, ".strokes.json") : svg;
}

fs::path Project::LooseCamerasPath() const {
  SYLVA_CHECK(camera_type_ == "manual") << "not a manually registered project";
  return Resolve(camera_path_);
}

std::vector<fs::path> Project::CameraSourceFiles() const {
  if (camera_type_ == "sfm") return {};
  const fs::path path = Resolve(camera_path_);
  if (camera_type_ != "colmap") return {path};
  std::vector<fs::path> files;
  for (const char* name : {"cameras", "images", "points3D"}) {
    for (const char* ext : {".txt", ".bin"}) files.push_back(path / (std::string(name) + ext));
  }
  return files;
}

std::vector<fs::path> Project::CameraFiles() const {
  return {RegisteredCamerasDir() / "cameras.json"};
}

ImageSet Project::LoadGivenCameras() const {
  SYLVA_CHECK(camera_type_ == "colmap" || camera_type_ == "sylva")
      << "the project's cameras are registered, not given";
  return ReadCameraSource(camera_type_, Resolve(camera_path_), nullptr);
}

ImageSet Project::LoadCameras() const {
  const fs::path dir = RegisteredCamerasDir();
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(dir / "cameras.json", ec), dir.string())
      << "no registered cameras yet; run the register stage first ('sylva register "
      << root_.string() << "' or 'sylva run')";
  return ReadCameraFile(dir / "cameras.json");
}

FloatImage Project::LoadMatte(const ImageSet& image_set, int view_idx) const {
  const View& view = image_set.views.at(view_idx);
  const Camera& camera = image_set.CameraOf(view);
  return LoadMatte(view.name, camera.width(), camera.height());
}

fs::path Project::DensityEditPath(const std::string& view_name) const {
  return FindMatteFile(EditsDir() / "density", view_name);
}

fs::path Project::CrownEditPath(const std::string& view_name) const {
  const fs::path path =
      EditsDir() / (fs::path(view_name).replace_extension().string() + ".crown.svg");
  std::error_code ec;
  return fs::is_regular_file(path, ec) ? path : fs::path();
}

FloatImage Project::LoadEditedMatte(const ImageSet& image_set, int view_idx) const {
  FloatImage matte = LoadMatte(image_set, view_idx);
  const std::string& name = image_set.views.at(view_idx).name;
  if (IsHeldOut(name)) return matte;
  const fs::path edit = DensityEditPath(name);
  if (!edit.empty()) ApplyDensityEdit(ReadImage(edit), edit.string(), &matte);
  const fs::path crown = CrownEditPath(name);
  if (!crown.empty()) {
    const FloatImage inside = OutlinedRegions(ReadSketchSvg(crown), matte.width(), matte.height());
    for (size_t i = 0; i < matte.values().size(); ++i) {
      if (inside.values()[i] > 0.0f) {
        matte.values()[i] = std::max(matte.values()[i], static_cast<float>(kCrownOutlineOpacity));
      }
    }
  }
  return matte;
}

FloatImage Project::LoadPaintedIn(const ImageSet& image_set, int view_idx) const {
  const std::string& name = image_set.views.at(view_idx).name;
  const fs::path edit = DensityEditPath(name);
  if (IsHeldOut(name) || edit.empty()) return FloatImage();
  const FloatImage matte = LoadMatte(image_set, view_idx);
  FloatImage painted = matte;
  ApplyDensityEdit(ReadImage(edit), edit.string(), &painted);
  return AddedOpacity(painted, matte);
}

FloatImage Project::LoadMatte(const std::string& view_name, int width, int height) const {
  const fs::path path = MattePath(view_name);
  if (matte_source_ == "computed") {
    std::error_code ec;
    SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), path.string())
        << "matte of photo '" << view_name << "' not computed yet; run the matte stage first "
        << "('sylva matte " << root_.string() << "' or 'sylva run')";
  }
  SYLVA_CHECK_INPUT(!path.empty(), (Resolve(mattes_) / view_name).string())
      << "no matte for photo '" << view_name
      << "' in the matte folder (same relative name, any image extension)";
  FloatImage matte = ReadMatte(path);
  SYLVA_CHECK_INPUT(matte.width() == width && matte.height() == height, path.string())
      << "matte is " << matte.width() << "x" << matte.height() << " but the photo is " << width
      << "x" << height;
  const bool has_foreground = std::any_of(matte.values().begin(), matte.values().end(),
                                          [](float a) { return a > kEmptyMatteAlpha; });
  SYLVA_CHECK_INPUT(has_foreground, path.string()) << "matte is empty (no foreground pixels)";
  return matte;
}

void Project::ApplySavedOptions(OptionRegistry* registry) const {
  registry->SetFromJson(ParseJson(options_json_, SettingsPath().string()), SettingsPath().string());
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
  json["photo_list"] = photo_names_;
  json["mattes"] = mattes_;
  json["matte_source"] = matte_source_;
  json["cameras"] = {{"type", camera_type_}, {"path", camera_path_}};
  json["units"] = units_;
  json["held_out"] = held_out_;
  if (!prior_views_.empty()) json["prior_views"] = prior_views_;
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
  if (root_json["format"].AsString() != kFormatName)
    root_json["format"].Fail("not a sylva project");
  if (root_json["version"].AsInt() != kFormatVersion)
    root_json["version"].Fail("unsupported version");
  project.photos_ = root_json["photos"].AsString();
  project.mattes_ = root_json["mattes"].AsString();
  project.camera_type_ = root_json["cameras"]["type"].AsString();
  if (project.camera_type_ != "colmap" && project.camera_type_ != "sylva" &&
      project.camera_type_ != "sfm" && project.camera_type_ != "manual") {
    root_json["cameras"]["type"].Fail("expected 'colmap', 'sylva', 'sfm' or 'manual'");
  }
  project.camera_path_ = root_json["cameras"]["path"].AsString();
  if (root_json.Has("matte_source")) {
    project.matte_source_ = root_json["matte_source"].AsString();
    if (project.matte_source_ != "given" && project.matte_source_ != "alpha" &&
        project.matte_source_ != "computed") {
      root_json["matte_source"].Fail("expected 'given', 'alpha' or 'computed'");
    }
  } else {
    project.matte_source_ = project.mattes_.empty() ? "alpha" : "given";
  }
  if (root_json.Has("photo_list")) {
    const JsonCursor list = root_json["photo_list"];
    for (size_t i = 0; i < list.Size(); ++i) project.photo_names_.push_back(list[i].AsString());
  } else {
    if (project.camera_type_ == "sfm" || project.camera_type_ == "manual") {
      root_json["photo_list"].Fail("missing (needed for registered cameras)");
    }
    for (const View& view : project.LoadGivenCameras().views) {
      project.photo_names_.push_back(view.name);
    }
  }
  project.units_ = root_json["units"].AsString();
  const JsonCursor held_out = root_json["held_out"];
  for (size_t i = 0; i < held_out.Size(); ++i) project.held_out_.push_back(held_out[i].AsString());
  if (root_json.Has("prior_views")) {
    const JsonCursor priors = root_json["prior_views"];
    for (size_t i = 0; i < priors.Size(); ++i) {
      project.prior_views_.push_back(priors[i].AsString());
    }
  }
  if (root_json.Has("options")) {
    if (!root_json["options"].IsObject()) root_json["options"].Fail("expected an object");
    project.options_json_ = root_json["options"].value().dump();
  }
  return project;
}

Project Project::Create(const ProjectSetup& setup) {
  CheckSetup(setup);
  // Build the project in a temporary folder beside the target, then rename.
  const fs::path root = fs::absolute(setup.root);
  const fs::path staging = TempPathBeside(root);
  fs::create_directories(staging);
  try {
    Project project;
    project.root_ = staging;
    project.held_out_ = setup.held_out;
    project.prior_views_ = setup.prior_views;
    project.photos_ = AbsoluteString(setup.photos_dir);
    project.mattes_ = setup.mattes_dir.empty() ? "" : AbsoluteString(setup.mattes_dir);
    const PhotoList photos = ReadPhotoList(setup);
    project.camera_type_ = photos.camera_type;
    project.photo_names_ = photos.names;
    project.units_ = !setup.units.empty()
                         ? setup.units
                         : (photos.file_units.empty() ? "arbitrary" : photos.file_units);
    CheckMatteNamesDiffer(project.photo_names_, setup.photos_dir);
    project.matte_source_ = FindMatteSource(project, setup);
    CheckInputFiles(project, photos.given);
    CheckHeldOut(project.photo_names_, setup.held_out);
    CheckPriorViews(project.photo_names_, setup.held_out, setup.prior_views);
    if (setup.register_method == "manual") CheckLoosePhotos(setup, project.photo_names_);
    project.camera_path_ = CopyCameraSource(setup, project.camera_type_, staging);
    if (setup.copy_inputs) {
      CopyViewFiles(project.photo_names_, setup.photos_dir, setup.mattes_dir, staging);
      project.photos_ = "photos";
      project.mattes_ = setup.mattes_dir.empty() ? "" : "mattes";
    }
    fs::create_directories(staging / "edits");
    project.Write();
    fs::rename(staging, root);
    project.root_ = root;
    return project;
  } catch (...) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    throw;
  }
}

}  // namespace sylva
