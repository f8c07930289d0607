// Registration with COLMAP (3.8, the Debian package's command line): runs
// feature extraction, matching and incremental mapping as child processes on a
// list of photos, and reads the resulting sparse model.
//
//   ColmapOptions options;            // defaults suit 2-50 photos of one tree
//   ColmapResult result = RunColmap(photos_dir, names, "", workspace, options, &progress);
//   // result.cameras: the registered photos, in COLMAP's arbitrary frame
//   //                 (see world_frame.h to put them upright);
//   // result.unregistered: the photos COLMAP could not place.
//
// The workspace holds what COLMAP writes, COLMAP-style:
//   <workspace>/database.db   features and matches
//   <workspace>/sparse/N/     the models (binary), N = 0, 1, ...
//   <workspace>/image_list.txt, colmap.log (all of COLMAP's output)
// (and sparse_retry/ while the mapper is retried). Each run starts afresh:
// these files are replaced, nothing else in the workspace is touched.
//
// COLMAP runs without a display (QT_QPA_PLATFORM=offscreen) and on the CPU
// (the Debian build has no CUDA). Each command runs in its own process group
// with its output captured to colmap.log, which is parsed for progress;
// cancelling through the ProgressReporter kills the group and throws
// Cancelled. Not thread-safe to run twice on one workspace.
#ifndef SYLVA_RECONSTRUCT_REGISTRATION_COLMAP_RUNNER_H_
#define SYLVA_RECONSTRUCT_REGISTRATION_COLMAP_RUNNER_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/check.h"
#include "core/util/progress.h"

namespace sylva {

struct ColmapOptions {
  // The colmap program: a path (containing '/'), or a name searched in PATH.
  std::string executable = "colmap";

  // How image pairs are chosen for matching:
  //   "exhaustive": every pair (best for unordered photos; cost grows as n^2);
  //   "sequential": each photo with its next `sequential_overlap` photos in
  //                 name order (photos taken walking around the tree), without
  //                 loop detection (it needs a vocabulary tree file);
  //   "auto":       exhaustive up to `exhaustive_max_photos` photos, else
  //                 sequential.
  std::string matcher = "auto";
  int exhaustive_max_photos = 50;
  // Sequential matching: neighbours matched after each photo (COLMAP's
  // SequentialMatching.overlap; it also adds the 2^k-th neighbours).
  int sequential_overlap = 10;

  // Pass the masks in RunColmap's masks_dir to COLMAP (ImageReader.mask_path):
  // features are only extracted where the mask is not black. Usually made from
  // the mattes with ColmapMaskFromMatte. Off by default: on ROMI's photos
  // masks made COLMAP faster but its poses worse (or fewer photos
  // registered), as the static background carries most of the matches;
  // they help when the background moves (people, wind in other trees).
  bool use_masks = false;

  // Photos are downscaled so their longer side is at most this (pixels)
  // before SIFT extraction (SiftExtraction.max_image_size). Smaller is faster
  // on the CPU; COLMAP's own default is 3200.
  int max_image_size = 1600;
  // Most SIFT features kept per photo (SiftExtraction.max_num_features).
  int max_num_features = 8192;

  // COLMAP's camera model for the photos: SIMPLE_PINHOLE, PINHOLE,
  // SIMPLE_RADIAL, RADIAL or OPENCV.
  std::string camera_model = "SIMPLE_RADIAL";
  // All photos share one camera (one body and lens, fixed zoom). Ignored
  // (each photo gets its own camera) when the photos' sizes differ.
  bool single_camera = true;

  // While photos stay unregistered, the mapper (only) runs again with the
  // next seed, up to this many runs in all; the run registering the most
  // photos is kept. Incremental mapping depends on its initial pair and
  // RANSAC draws: on 8 of ROMI's photos 15 degrees apart, one run in ~15
  // registered only 2. Mapping costs little beside matching (on 72 photos,
  // 2-3 minutes against 3-20).
  // Retries use relaxed thresholds (half COLMAP's inliers and initial
  // triangulation angle).
  int mapper_attempts = 3;
  // When fewer than this share of the photos are registered after the
  // mapper's attempts, matching runs again from the same features (guided)
  // and the mapper too; the better model is kept. 0 = never.
  double rematch_below = 0.5;

  // Threads for each COLMAP command; -1 = all cores.
  int num_threads = -1;
  // A COLMAP command that writes nothing and uses no CPU time for this long
  // has hung (its threads can deadlock: feature_extractor did once here,
  // after a photo with no features) and is stopped, then run once more
  // (feature extraction from a fresh database; matching goes on from its
  // database); hung twice, or a hung mapper, is a RegistrationError. In
  // seconds; 0 waits for ever. Work in progress always uses CPU time.
  double stall_seconds = 120.0;
  // COLMAP's random seed (its RANSAC sampling). COLMAP is not reproducible on
  // the CPU even so: its matches differ slightly from run to run, with one
  // thread too, and so do the poses.
  int random_seed = 0;

  // Throws InputError("Colmap.<field>", ...) for the first invalid field.
  void Check() const;
};

// What RunColmap produced.
struct ColmapResult {
  // The largest model COLMAP built, in COLMAP's frame and scale (arbitrary),
  // with its sparse points. Views are named as in `photo_names`.
  ImageSet cameras;
  // Photos not in `cameras` (in the order given): COLMAP could not register
  // them, or registered them in a smaller, separate model.
  std::vector<std::string> unregistered;
  // Models COLMAP built (1 when every registered photo is in one model).
  int num_models = 0;
  // Mapper runs (see ColmapOptions::mapper_attempts).
  int mapper_runs = 0;
  // Whether the kept model came from a run with relaxed thresholds, and how
  // many matching passes ran (2 when the first registered too few photos).
  bool relaxed_mapping = false;
  int matching_runs = 1;
  // What went wrong on the way without stopping the registration (a mapper
  // retry that failed, a second matching pass, a hung command run again),
  // for the stage's warnings.
  std::vector<std::string> notes;
  // The matcher used ("exhaustive" or "sequential") and whether the photos
  // shared one camera.
  std::string matcher;
  bool single_camera = true;

  // Wall time of each COLMAP command, and their sum (seconds).
  double extraction_seconds = 0.0;
  double matching_seconds = 0.0;
  double mapping_seconds = 0.0;
  double colmap_seconds = 0.0;
  // Wall time RunColmap spent itself: checking the photos, writing the image
  // list, starting processes, reading the models (seconds).
  double sylva_seconds = 0.0;

  // All of COLMAP's output.
  std::filesystem::path log_path;

  // "COLMAP registered 70 of 72 photos (1 model; exhaustive matching;
  //  extraction 12.1 s, matching 80.3 s, mapping 20.5 s; sylva 0.4 s)".
  std::string BriefReport() const;
};

// The photos could not be registered: a COLMAP command failed, or COLMAP
// found too few matches to build a model of at least 2 photos. It is an
// InputError because the cause is nearly always the photos (too few, too
// little overlap, blurred, featureless) or the COLMAP installation, and front
// ends report it as such. source() names the photo folder; the message says
// what happened, quotes the end of COLMAP's log and gives the log's path.
class RegistrationError : public InputError {
 public:
  RegistrationError(const std::string& source, const std::string& message,
                    std::filesystem::path log_path)
      : InputError(source, message), log_path_(std::move(log_path)) {}
  const std::filesystem::path& log_path() const { return log_path_; }

 private:
  std::filesystem::path log_path_;
};

// Registers `photo_names` (paths relative to `photos_dir`, sub-folders allowed,
// e.g. "side/30.jpg") with COLMAP into `workspace` (created if needed). With
// options.use_masks, `masks_dir` holds one mask per photo at
// ColmapMaskPath(masks_dir, name). `progress` may be null.
//
// Throws:
//   InputError        bad options; a photo or mask missing or unreadable;
//                     COLMAP not found ("Colmap.executable");
//   RegistrationError a COLMAP command failed or crashed; no model; the
//                     largest model has fewer than 2 photos;
//   Cancelled         the reporter asked to stop (COLMAP is killed first).
// Partial success is success: photos COLMAP did not register are listed in
// ColmapResult::unregistered (and logged).
ColmapResult RunColmap(const std::filesystem::path& photos_dir,
                       const std::vector<std::string>& photo_names,
                       const std::filesystem::path& masks_dir,
                       const std::filesystem::path& workspace, const ColmapOptions& options,
                       ProgressReporter* progress);

// Where COLMAP looks for the mask of `photo_name`: <masks_dir>/<photo_name>.png
// (e.g. masks/side/30.jpg.png).
std::filesystem::path ColmapMaskPath(const std::filesystem::path& masks_dir,
                                     const std::string& photo_name);

// A COLMAP mask from an alpha matte (one channel): white (1) where the matte
// exceeds `threshold` or lies within `dilation_px` pixels (Chebyshev
// distance) of such a pixel, black (0) elsewhere. One channel, the matte's
// size. The dilation keeps some background around the tree, where most of
// the matchable texture is: on ROMI's 24 photos 15 degrees apart (1616x1080),
// masks dilated by 8 px let COLMAP register 2 of 24, by 60 px all 24
// (without masks: all 24, with smaller pose errors).
FloatImage ColmapMaskFromMatte(const FloatImage& matte, float threshold = 0.5f,
                               int dilation_px = 60);

// The colmap program that RunColmap would start: `executable` itself if it
// contains '/', else the first executable file of that name in PATH. Throws
// InputError("Colmap.executable", "colmap not found: ...") if there is none.
std::filesystem::path FindColmapExecutable(const std::string& executable);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_REGISTRATION_COLMAP_RUNNER_H_
