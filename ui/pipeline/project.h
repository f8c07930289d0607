// The on-disk project shared by the CLI and the desktop app (one tree):
//
//   PROJECT/sylva.json   photo list and folder, matte source, camera source,
//                        held-out views, options that differ from the defaults
//   PROJECT/cameras/     a copy of the camera model or loose-camera file
//                        given at init (none when COLMAP registers the photos)
//   PROJECT/photos/, mattes/  copies of the inputs (with --copy; otherwise
//                        sylva.json refers to the original folders)
//   PROJECT/edits/       what a person made: trimaps/<photo>.png (painted
//                        matting hints), <photo>.strokes.svg|json (drawn
//                        attractor strokes), <photo>.attractors.json (a whole
//                        attractor graph), density/<photo>.png (painted
//                        density, reconstruct/density/density_edits.h),
//                        <photo>.crown.svg (crown outlines drawn over it)
//   PROJECT/cache/       stage records keyed by a hash of their inputs; the
//                        COLMAP workspace (cache/colmap/)
//   PROJECT/out/         outputs: cameras/ (the registered cameras in sylva's
//                        world frame: cameras.json, and colmap/ as a COLMAP
//                        text model unless a camera is orthographic;
//                        registration.json, unregistered.txt), mattes/
//                        (computed mattes, 8-bit PNG), density.vdb,
//                        attractors/ (graphs and overlays), skeleton, tree,
//                        report
//
// sylva.json:
// { "format": "sylva-project", "version": 1,
//   "photos": "photos" | "/abs/dir", "photo_list": ["a.jpg", "side/b.jpg"],
//   "mattes": "mattes" | "/abs/dir" | "",
//   "matte_source": "given" | "alpha" | "computed",
//   "cameras": {"type": "colmap" | "sylva" | "sfm" | "manual", "path": "cameras/..."},
//   "units": "arbitrary", "held_out": ["heldout_00.png"],
//   "prior_views": ["front.depth.png"],
//   "options": {"Density": {"resolution": 64}} }
// Relative paths are relative to the project folder. Camera types: "colmap"
// and "sylva" are given models; "sfm" registers the photos with COLMAP;
// "manual" registers them from a loose-camera file (azimuths, correspondences).
// "prior_views" (optional) are input views no camera took: a single
// drawing's made-up side view (sketch/sketch_views.h); the report leaves them
// out of its fidelity figures.
// Whatever the source, the register stage writes the cameras the later stages
// use to out/cameras/. Projects written before "photo_list" and
// "matte_source" existed take the list from the camera model and the source
// from "mattes" ("" = the photos' alpha channels).
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

// The matte value inside crown outlines drawn over a photo (alpha; as a
// drawn crown's, Sketch.crown_opacity's default).
constexpr double kCrownOutlineOpacity = 0.6;

// What `sylva init` is given.
struct ProjectSetup {
  fs::path root;
  fs::path photos_dir;
  // Exactly one camera source: a given COLMAP model or sylva camera file, or
  // registration ("colmap": structure from motion on the photos; "manual":
  // from loose_cameras_file).
  fs::path colmap_model_dir;
  fs::path camera_file;
  std::string register_method;
  fs::path loose_cameras_file;
  // Optional: a folder of mattes. Without it the photos' alpha channels are
  // the mattes if every photo has one, else the matte stage computes them.
  fs::path mattes_dir;
  std::vector<std::string> held_out;
  std::vector<std::string> prior_views;  // Project::IsPriorView
  bool copy_inputs = false;              // copy photos and mattes into the project
  std::string units;                     // empty: from the camera file, else "arbitrary"
};

// View names as `sylva init --held-out` and the new-project wizard take
// them: comma-separated ("a.png, b.png"), or "@FILE" for a file of one name
// per line; surrounding blanks and empty names are dropped.
std::vector<std::string> ParseViewNames(const std::string& value);

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
  // Input views that are priors, not photographs (a drawing's made-up depth
  // view): used like the others, but not a measure of the reconstruction.
  const std::vector<std::string>& prior_views() const { return prior_views_; }
  // Every photo of the project (relative names, sorted).
  const std::vector<std::string>& photo_names() const { return photo_names_; }
  const std::string& camera_type() const { return camera_type_; }
  bool RegistersWithColmap() const { return camera_type_ == "sfm"; }
  bool RegistersManually() const { return camera_type_ == "manual"; }
  bool ComputesMattes() const { return matte_source_ == "computed"; }

  // The cameras given at init (types "colmap" and "sylva"); the register
  // stage takes them into sylva's world frame.
  ImageSet LoadGivenCameras() const;
  // The loose-camera file of a "manual" project.
  fs::path LooseCamerasPath() const;
  // Files of the camera source given at init (none for "sfm").
  std::vector<fs::path> CameraSourceFiles() const;

  // The registered cameras (out/cameras/cameras.json, written by the
  // register stage).
  // InputError if the register stage has not run yet.
  ImageSet LoadCameras() const;
  fs::path RegisteredCamerasDir() const { return OutDir() / "cameras"; }
  // Files whose change makes camera-dependent stages out of date.
  std::vector<fs::path> CameraFiles() const;
  fs::path PhotoPath(const std::string& view_name) const;
  fs::path PhotosDir() const;
  // The matte file of a view: in the matte folder, the photo itself when
  // the photos carry alpha, or out/mattes/<name>.png when computed.
  fs::path MattePath(const std::string& view_name) const;
  // Where the matte stage writes a photo's matte (computed mattes only).
  fs::path ComputedMattePath(const std::string& view_name) const;
  // A painted trimap hint for a photo: edits/trimaps/<name>.png (any image
  // extension); empty path if there is none.
  fs::path TrimapHintPath(const std::string& view_name) const;
  // Attractor graphs (issue 5). What the attract stage writes for a photo:
  // out/attractors/<name>.json (the graph) and <name>.png (the overlay),
  // <name> the photo's name without extension; and the index
  // out/attractors/attractors.json.
  fs::path AttractorGraphPath(const std::string& view_name) const;
  fs::path AttractorOverlayPath(const std::string& view_name) const;
  fs::path AttractorIndexPath() const { return OutDir() / "attractors" / "attractors.json"; }
  // What a person made for a photo: a whole graph, edits/<name>.attractors.json
  // (overrides everything else), or drawn strokes, edits/<name>.strokes.svg
  // or edits/<name>.strokes.json (SVG first); empty paths if none exist.
  fs::path AttractorEditPath(const std::string& view_name) const;
  fs::path StrokesPath(const std::string& view_name) const;
  // Density painted on a photo (reconstruct/density/density_edits.h):
  // edits/density/<name>.png (any image extension, with alpha); empty path
  // if there is none.
  fs::path DensityEditPath(const std::string& view_name) const;
  // Crown outlines drawn over a photo (issue 14: the sketch editors on
  // photos): edits/<name>.crown.svg, where every shape (closed by the chord
  // between its ends if open) outlines crown: the matte is raised to at
  // least kCrownOutlineOpacity inside. Empty path if there is none.
  fs::path CrownEditPath(const std::string& view_name) const;
  // Reads and validates a view's matte: the camera's size, not empty.
  FloatImage LoadMatte(const ImageSet& image_set, int view_idx) const;
  // The matte the stages from the density on read: LoadMatte with the
  // view's density edit mixed in, then its crown outlines filled to at
  // least kCrownOutlineOpacity (held-out views are left as they are: they
  // judge the reconstruction).
  FloatImage LoadEditedMatte(const ImageSet& image_set, int view_idx) const;
  // The opacity the view's density edit adds over its matte
  // (AddedOpacity: where a person painted the tree in); an empty image if
  // the view has no density edit or is held out.
  FloatImage LoadPaintedIn(const ImageSet& image_set, int view_idx) const;
  // Reads and validates the matte of a photo of the given size.
  FloatImage LoadMatte(const std::string& view_name, int width, int height) const;

  // Options stored in sylva.json, applied over the registry's values.
  void ApplySavedOptions(OptionRegistry* registry) const;
  // Stores the registry's non-default options in sylva.json (atomically).
  void SaveOptions(const OptionRegistry& registry);

 private:
  void Write() const;  // sylva.json, atomically
  fs::path Resolve(const std::string& path) const;

  fs::path root_;
  std::string photos_;
  std::vector<std::string> photo_names_;
  std::string mattes_;
  std::string matte_source_ = "given";  // "given", "alpha" or "computed"
  std::string camera_type_;             // "colmap", "sylva", "sfm" or "manual"
  std::string camera_path_;
  std::string units_ = "arbitrary";
  std::vector<std::string> held_out_;
  std::vector<std::string> prior_views_;
  std::string options_json_ = "{}";
};

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PROJECT_H_
