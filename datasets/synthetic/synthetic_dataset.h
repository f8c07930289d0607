// A synthetic photo set of a synthetic tree: cameras, rendered photos and
// exact mattes, plus held-out views, with the tree's ground-truth skeleton
// and mesh. The oracle for registration-free tests of every later stage.
//
// Cameras look at the centre of the tree's bounding box from a ring around it:
//   - pinhole: K input views at azimuths k 360/K degrees and elevation
//     `elevation_deg`, with a `fov_deg` field of view (PINHOLE, or
//     SIMPLE_RADIAL when radial_distortion != 0), all at one distance chosen
//     so that the whole bounding box is inside every image with a margin;
//   - orthographic: K input views at azimuths k 180/K degrees and elevation 0
//     (K = 2: two views at right angles, as in Neubert's thesis), with one
//     scale that fits the bounding box in every view.
// Held-out views (same camera kind) lie half-way between input azimuths, at
// elevation `held_out_elevation_deg`. All views share camera id 1. Image ids
// are 1..N, input views first ("view_00.png", ...), then held-out views
// ("heldout_00.png", ...). Azimuth 0 looks from +X towards the tree.
#ifndef SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_DATASET_H_
#define SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_DATASET_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "core/util/progress.h"
#include "datasets/synthetic/synthetic_tree.h"

namespace sylva {

enum class SyntheticCameraKind { kPinhole, kOrthographic };

std::string SyntheticCameraKindName(SyntheticCameraKind kind);  // "pinhole", "orthographic"

struct SyntheticDatasetOptions {
  // Seed of the tree (GenerateSyntheticTree).
  uint64_t seed = 1;
  // Input views (>= 1) and held-out views (>= 0).
  int num_views = 8;
  int num_held_out = 2;
  SyntheticCameraKind camera = SyntheticCameraKind::kPinhole;
  // Width and height of the square images, in pixels (>= 8).
  int image_size = 512;
  // Rays per pixel along each axis when rendering (>= 1); mattes are exact
  // coverage up to 1 / samples_per_axis^2.
  int samples_per_axis = 4;
  // Elevation of the pinhole input views above the bounding box centre, in
  // degrees, in (-90, 90). Orthographic input views are always at 0.
  double elevation_deg = 10.0;
  // Elevation of the held-out views, in degrees, in (-90, 90).
  double held_out_elevation_deg = 25.0;
  // Pinhole field of view across the image, in degrees, in (0, 170).
  double fov_deg = 47.0;
  // Fraction of the image half-size left free around the tree's bounding box
  // (in the tightest view), in [0, 0.9).
  double margin = 0.05;
  // k of a SIMPLE_RADIAL camera if non-zero (pinhole only), in [-0.5, 0.5].
  double radial_distortion = 0.0;
  SyntheticTreeOptions tree;

  // Throws InputError naming the first violated constraint.
  void Check() const;
};

struct SyntheticDataset {
  SyntheticTree tree;
  ImageSet image_set;                 // all views, input views first, then held-out views
  std::vector<std::string> held_out;  // names of the held-out views
  std::vector<FloatImage> photos;     // RGBA straight alpha, one per view (image_set order)
  std::vector<FloatImage> mattes;     // 1 channel, exact coverage, one per view
  std::string units = "m";

  bool IsHeldOut(const std::string& name) const;
  // Per view of image_set: held out or not.
  std::vector<bool> HeldOutFlags() const;
  // The views a reconstruction may use (all but the held-out ones) and
  // their mattes, in image_set's order.
  ImageSet InputImageSet() const;
  std::vector<FloatImage> InputMattes() const;
};

// Generates the tree, places the cameras and renders every view (parallel
// over rows; a few seconds for the defaults on two cores). Reports progress
// per view and throws Cancelled if asked to stop.
SyntheticDataset MakeSyntheticDataset(const SyntheticDatasetOptions& options,
                                      ProgressReporter* progress = nullptr);

// The same for a tree made elsewhere (e.g. the bark of a laser-scanned QSM
// and its skeleton as the truth): options.tree and options.seed are unused.
SyntheticDataset RenderSyntheticDataset(SyntheticTree tree, const SyntheticDatasetOptions& options,
                                        ProgressReporter* progress = nullptr);

// The cameras alone (no rendering) for a tree, as MakeSyntheticDataset places
// them.
ImageSet MakeSyntheticCameras(const SyntheticDatasetOptions& options, const TriangleMesh& mesh);

// Writes the dataset into `out_dir` (created; InputError if it exists and is
// not empty), every file atomically:
//   photos/<name>            RGBA, 8-bit PNG (straight alpha)
//   mattes/<name>            grayscale, 16-bit PNG
//   colmap/{cameras,images,points3D}.txt   (pinhole only)
//   cameras.json             sylva camera file (always; units "m")
//   held_out.txt             names of the held-out views, one per line
//   ground_truth/skeleton.json, ground_truth/tree.obj (+ tree.mtl)
//   synth.json               the options, seed, units and counts
void WriteSyntheticDataset(const SyntheticDataset& dataset, const SyntheticDatasetOptions& options,
                           const std::filesystem::path& out_dir);

}  // namespace sylva

#endif  // SYLVA_DATASETS_SYNTHETIC_SYNTHETIC_DATASET_H_
