// The on-disk project shared by the CLI and the desktop app (one tree):
//
//   PROJECT/sylva.json   photo and matte folders, camera source, held-out
//                        views, options that differ from the defaults
//   PROJECT/cameras/     a copy of the camera model given at init
//   PROJECT/photos/, mattes/  copies of the inputs (with --copy; otherwise
//                        sylva.json refers to the original folders)
//   PROJECT/edits/       what a person made (painted density, strokes)
//   PROJECT/cache/       stage records keyed by a hash of their inputs
//   PROJECT/out/         outputs (density.vdb, report.json, ...)
//
// sylva.json:
// { "format": "sylva-project", "version": 1,
//   "photos": "photos" | "/abs/dir", "mattes": "mattes" | "/abs/dir" | "",
//   "cameras": {"type": "colmap" | "sylva", "path": "cameras/..."},
//   "units": "arbitrary", "held_out": ["heldout_00.png"],
//   "options": {"Density": {"resolution": 64}} }
// Relative paths are relative to the project folder. An empty "mattes"
// means the photos' alpha channels are the mattes.
#ifndef SYLVA_UI_PIPELINE_PROJECT_H_
#define SYLVA_UI_PIPELINE_PROJECT_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "ui/pipeline/option_registry.h"

namespace sylva {

namespace fs = std::filesystem;

// What `sylva init` is given.
struct ProjectSetup {
  fs::path root;
  fs::path photos_dir;
  fs::path colmap_model_dir;  // exactly one of colmap_model_dir, camera_file
  fs::path camera_file;
  fs::path mattes_dir;        // optional
  std::vector<std::string> held_out;
  bool copy_inputs = false;   // copy photos and mattes into the project
  std::string units;          // empty: from the camera file, else "arbitrary"
};

class Project {
 public:
  // Validates the inputs (every photo of the model present, of the camera's
  // size, with a matte) and writes the project folder. Nothing is left
  // behind on error. Throws InputError naming the offending file or flag.
  static Project Create(const ProjectSetup& setup);
  // Reads PROJECT/sylva.json; throws InputError naming it if invalid.
  static Project Open(const fs::path& root);

  const fs::path& root() const { return root_; }
  fs::path SettingsPath() const { return root_ / "sylva.json"; }
  fs::path OutDir() const { return root_ / "out"; }
  fs::path CacheDir() const { return root_ / "cache"; }
  fs::path EditsDir() const { return root_ / "edits"; }
  const std::string& units() const { return units_; }
  const std::vector<std::string>& held_out() const { return held_out_; }
  bool IsHeldOut(const std::string& view_name) const;

  // The registered cameras (validated against the photos on disk).
  ImageSet LoadCameras() const;
  // Files whose change makes camera-dependent stages out of date.
  std::vector<fs::path> CameraFiles() const;
  fs::path PhotoPath(const std::string& view_name) const;
  // The matte file of a view: in the matte folder, or the photo itself when
  // the photos carry alpha.
  fs::path MattePath(const std::string& view_name) const;
  // Reads and validates a view's matte: the camera's size, not empty.
  FloatImage LoadMatte(const ImageSet& image_set, int view_idx) const;

  // Options stored in sylva.json, applied over the registry's values.
  void ApplySavedOptions(OptionRegistry* registry) const;
  // Stores the registry's non-default options in sylva.json (atomically).
  void SaveOptions(const OptionRegistry& registry);

 private:
  void Write() const;  // sylva.json, atomically
  fs::path Resolve(const std::string& path) const;

  fs::path root_;
  std::string photos_;
  std::string mattes_;
  std::string camera_type_;  // "colmap" or "sylva"
  std::string camera_path_;
  std::string units_ = "arbitrary";
  std::vector<std::string> held_out_;
  std::string options_json_ = "{}";
};

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PROJECT_H_
