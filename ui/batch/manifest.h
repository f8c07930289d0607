// A batch manifest: one tree per row of a CSV file, each becoming the project
// OUT_DIR/<name>/ that `sylva init` + `sylva run` would make.
//
//   name,photos,cameras,mattes,held_out,units,Density.resolution
//   oak-17,oak-17/photos,oak-17/cameras.json,oak-17/mattes,@oak-17/held_out.txt,m,
//   oak-18,oak-18/photos,oak-18/cameras.json,,,m,96
//
// Columns (any order; a header row names them, and unknown names are errors):
//   name           the project folder's name: letters, digits, '.', '_', '-',
//                  '+', not starting with '.'; unique (also ignoring case),
//                  not "logs" (the batch's log folder)
//   photos         folder of the photos (required)
//   colmap         a COLMAP sparse model folder, or
//   cameras        a sylva camera file (core/io/camera_file.h), or
//   register       colmap | manual (with loose_cameras, a loose-camera file):
//                  exactly one camera source per row
//   mattes         folder of alpha mattes (optional)
//   held_out       views kept out of the reconstruction: names separated by
//                  ';' or ',' (quote the cell for commas), or @FILE with one
//                  name per line (optional)
//   units          world units of the cameras (optional)
//   Section.field  a pipeline option for this tree only (`sylva help
//                  options`); an empty cell leaves the batch's value
// Paths are relative to the manifest's folder (or absolute). '-' may stand
// for '_' in column names (loose-cameras, held-out). Lines starting with '#'
// are comments.
//
// The reader checks everything it can without running a tree: columns, names,
// that paths exist, one camera source per row, option names. An option's
// value is checked when its tree runs (a bad value fails that tree only).
#ifndef SYLVA_UI_BATCH_MANIFEST_H_
#define SYLVA_UI_BATCH_MANIFEST_H_

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ui/pipeline/project.h"

namespace sylva {

namespace fs = std::filesystem;

struct ManifestTree {
  int line = 0;  // the row's line in the manifest (1-based), for messages
  std::string name;
  // Absolute paths; empty when not given.
  fs::path photos_dir;
  fs::path colmap_model_dir;
  fs::path camera_file;
  std::string register_method;  // "", "colmap" or "manual"
  fs::path loose_cameras_file;
  fs::path mattes_dir;
  std::vector<std::string> held_out;
  std::string units;
  // Per-tree options (Section.field, value) of the non-empty option cells.
  std::vector<std::pair<std::string, std::string>> options;

  // What `sylva init OUT_DIR/<name> ...` is given for this row.
  ProjectSetup Setup(const fs::path& out_dir) const;
  // A hash of what the project is made from (paths, held-out views, units;
  // not the options): a project made from other inputs is not this row's.
  std::string InputsKey() const;
};

struct Manifest {
  fs::path path;  // absolute
  std::vector<ManifestTree> trees;

  // The tree named `name`; nullptr if there is none.
  const ManifestTree* Find(const std::string& name) const;
};

// Reads and checks a manifest. Throws InputError("FILE:LINE", problem) for
// the first problem found (FILE alone for problems of the whole file).
Manifest ReadManifest(const fs::path& path);
Manifest ParseManifest(const std::string& text, const fs::path& path);

// A manifest of every tree folder under `dir` (its sub-folders, sorted by
// name). A tree folder holds its photos in photos/ or images/ (else in
// itself), cameras as cameras.json, a COLMAP model (colmap/, sparse/0/ or
// sparse/), or a loose-camera file (loose_cameras.json: registered by hand);
// without any, COLMAP registers the photos. mattes/ and held_out.txt are
// used when present. Sub-folders without photos are skipped. Throws
// InputError naming `dir` if it holds no tree folder.
std::vector<ManifestTree> ScanTreeFolders(const fs::path& dir);

// The manifest text of `trees`, paths relative to `manifest_dir` (where the
// manifest will be written).
std::string ManifestText(const std::vector<ManifestTree>& trees, const fs::path& manifest_dir);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_MANIFEST_H_
