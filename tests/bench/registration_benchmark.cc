// Registration on real photos: COLMAP (through RunColmap) against a set's own
// cameras, with and without masks, and the world frame (EstimateWorldFrame)
// on the given cameras and on COLMAP's. Prints counts, pose errors after a
// similarity alignment, and where the time goes (each COLMAP command, and
// sylva's own overhead beside it).
//
//   sylva_registration_benchmark --photos=DIR --truth=MODEL_DIR --workspace=DIR
//       [--every=K] [--first=N] [--masks=0|1|both] [--mask_dilation=PX]
//       [--max_image_size=PX] [--matcher=auto|exhaustive|sequential]
//       [--threads=N] [--world_frame_only]
//   sylva_registration_benchmark --quick      (smoke test on 6 bundled photos)
//
// Photos are the files of DIR (sorted), every K-th from the first (or the
// first N). Masks and mattes follow ROMI's simple rule (bright and not
// orange, registration_test_util.h), so this tool is meant for ROMI's
// real_plant photos. Position errors are given in % of the truth's camera
// ring radius (mean distance of its camera centres from their centroid).
//
// There is no reference implementation to agree with: COLMAP is compared
// with the set's own cameras (the truth), and the program fails when the
// registration or the world frame strays from them beyond the tolerances
// below (tests/bench/agreement.h).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/util/check.h"
#include "reconstruct/registration/colmap_runner.h"
#include "reconstruct/registration/registration_test_util.h"
#include "reconstruct/registration/world_frame.h"
#include "tests/bench/agreement.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

struct Settings {
  fs::path photos;
  fs::path truth;
  fs::path workspace;
  int every = 1;
  int first = 0;  // 0 = all
  std::string masks = "0";
  int mask_dilation = 60;  // ColmapMaskFromMatte's default
  bool world_frame_only = false;
  ColmapOptions colmap;
};

// Applies one --name=value flag; false if unknown.
bool ApplyFlag(const std::string& name, const std::string& value, Settings* settings) {
  if (name == "photos")
    settings->photos = value;
  else if (name == "truth")
    settings->truth = value;
  else if (name == "workspace")
    settings->workspace = value;
  else if (name == "every")
    settings->every = std::stoi(value);
  else if (name == "first")
    settings->first = std::stoi(value);
  else if (name == "masks")
    settings->masks = value;
  else if (name == "mask_dilation")
    settings->mask_dilation = std::stoi(value);
  else if (name == "max_image_size")
    settings->colmap.max_image_size = std::stoi(value);
  else if (name == "matcher")
    settings->colmap.matcher = value;
  else if (name == "threads")
    settings->colmap.num_threads = std::stoi(value);
  else if (name == "world_frame_only")
    settings->world_frame_only = value != "0";
  else
    return false;
  return true;
}

// CPU time (user + system) this process has used so far, in seconds: what
// RunColmap itself costs, apart from the COLMAP processes it waits for.
double ProcessCpuSeconds() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<std::string> ChoosePhotos(const Settings& settings) {
  const std::vector<std::string> all = SortedFileNames(settings.photos);
  std::vector<std::string> chosen;
  for (size_t i = 0; i < all.size(); i += settings.every) {
    if (settings.first > 0 && static_cast<int>(chosen.size()) == settings.first) break;
    chosen.push_back(all[i]);
  }
  return chosen;
}

double RingRadius(const ImageSet& cameras) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const View& view : cameras.views) mean += view.ProjectionCenter() / cameras.NumViews();
  double sum = 0;
  for (const View& view : cameras.views) sum += (view.ProjectionCenter() - mean).norm();
  return sum / cameras.NumViews();
}

// One matte per view of `cameras` (ROMI's rule), box-downsampled by 4.
std::vector<FloatImage> MakeMattes(const ImageSet& cameras, const fs::path& photos) {
  constexpr int kMatteReduction = 4;
  std::vector<FloatImage> mattes;
  for (const View& view : cameras.views) {
    mattes.push_back(DownsampleBox(RomiMatte(ReadImage(photos / view.name)), kMatteReduction));
  }
  return mattes;
}

void WriteMasks(const std::vector<std::string>& names, const Settings& settings,
                const fs::path& masks_dir) {
  for (const std::string& name : names) {
    const FloatImage matte = RomiMatte(ReadImage(settings.photos / name));
    WriteImage(ColmapMaskPath(masks_dir, name),
               ColmapMaskFromMatte(matte, 0.5f, settings.mask_dilation));
  }
}

void PrintWorldFrame(const char* label, const WorldFrame& frame, double seconds) {
  std::printf("%s: %s\n  up (model) %.5f %.5f %.5f; base (model) %.1f %.1f %.1f; %.2f s\n", label,
              frame.BriefReport().c_str(), frame.up_in_model.x(), frame.up_in_model.y(),
              frame.up_in_model.z(), frame.base_in_model.x(), frame.base_in_model.y(),
              frame.base_in_model.z(), seconds);
}

// World frame on the given cameras; returns it for comparison with COLMAP's.
WorldFrame RunWorldFrame(const ImageSet& truth, const std::vector<FloatImage>& mattes) {
  const auto start = std::chrono::steady_clock::now();
  const WorldFrame frame = EstimateWorldFrame(truth, mattes, WorldFrameOptions());
  PrintWorldFrame("world frame on the given cameras", frame, Seconds(start));
  const double up_error = std::acos(std::clamp(-frame.up_in_model.z(), -1.0, 1.0)) * 180 / M_PI;
  std::printf("  up vs the given frame's -Z: %.4f deg\n", up_error);
  return frame;
}

// Tolerances against the truth, from two quick runs (6 ROMI photos at 640
// px: 6 of 6 registered, rotation error median 0.24 and 0.19 deg, position
// error median 0.08 and 0.07 % of the ring radius, world frame up 0.31 deg
// from the given cameras'), about 4-6x those: COLMAP's randomness moves
// them a little, a broken registration (a wrong camera model, a lost model)
// by degrees.
constexpr double kMaxMedianRotationDeg = 1.0;
constexpr double kMaxMedianPositionPercent = 0.5;
constexpr double kMaxWorldUpDeg = 1.5;

// COLMAP's cameras with their own world frame, compared with the given ones.
void CompareWorldFrames(const ColmapResult& result, const ImageSet& truth,
                        const std::vector<FloatImage>& all_mattes, const WorldFrame& given,
                        Agreement* agreement) {
  std::vector<FloatImage> mattes;
  for (const View& view : result.cameras.views)
    mattes.push_back(all_mattes[truth.FindView(view.name)]);
  const auto start = std::chrono::steady_clock::now();
  const WorldFrame frame = EstimateWorldFrame(result.cameras, mattes, WorldFrameOptions());
  PrintWorldFrame("  world frame on COLMAP's cameras", frame, Seconds(start));
  const PoseErrors errors = ComparePoses(result.cameras, truth);
  const Sim3d& truth_from_colmap = errors.truth_from_estimate;
  const Eigen::Vector3d up_in_truth = (truth_from_colmap.rotation * frame.up_in_model).normalized();
  const Eigen::Vector3d base_in_truth = truth_from_colmap * frame.base_in_model;
  const double up_deg =
      std::acos(std::clamp(up_in_truth.dot(given.up_in_model), -1.0, 1.0)) * 180 / M_PI;
  std::printf(
      "  in the given frame: up %.4f deg from the given cameras' up; base %.1f %.1f %.1f "
      "(%.1f from the given cameras' base); height %.1f (given cameras: %.1f)\n",
      up_deg, base_in_truth.x(), base_in_truth.y(), base_in_truth.z(),
      (base_in_truth - given.base_in_model).norm(), frame.tree_height * truth_from_colmap.scale,
      given.tree_height);
  agreement->AtMost("world frame up on COLMAP's cameras vs the given cameras' (deg)", up_deg,
                    kMaxWorldUpDeg);
}

void RunOnce(const Settings& settings, bool use_masks, const std::vector<std::string>& names,
             const ImageSet& truth, const std::vector<FloatImage>& mattes, const WorldFrame& given,
             Agreement* agreement) {
  const fs::path workspace = settings.workspace / (use_masks ? "masks_on" : "masks_off");
  const fs::path masks_dir = workspace / "masks";
  double mask_seconds = 0;
  if (use_masks) {
    const auto start = std::chrono::steady_clock::now();
    WriteMasks(names, settings, masks_dir);
    mask_seconds = Seconds(start);
  }
  ColmapOptions options = settings.colmap;
  options.use_masks = use_masks;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuSeconds();
  const ColmapResult result =
      RunColmap(settings.photos, names, masks_dir, workspace, options, nullptr);
  const double total = Seconds(start);
  const double sylva_cpu = ProcessCpuSeconds() - cpu_start;
  std::printf("\n[masks %s] %s\n", use_masks ? "on" : "off", result.BriefReport().c_str());
  std::printf(
      "  time: COLMAP %.2f s (extraction %.2f, matching %.2f, mapping %.2f); sylva "
      "overhead %.3f s wall (%.2f%%), %.3f s CPU in sylva's process; RunColmap wall %.2f s; "
      "writing masks %.2f s\n",
      result.colmap_seconds, result.extraction_seconds, result.matching_seconds,
      result.mapping_seconds, result.sylva_seconds,
      100 * result.sylva_seconds / result.colmap_seconds, sylva_cpu, total, mask_seconds);
  const std::string masks = use_masks ? " (masks on)" : " (masks off)";
  // All registered in every run so far; one may drop on another machine.
  agreement->AtLeast("registered photos" + masks, result.cameras.NumViews(),
                     static_cast<double>(names.size()) - 1);
  if (result.cameras.NumViews() < 3) {
    std::printf("  registered %d of %zu: too few to compare poses\n", result.cameras.NumViews(),
                names.size());
    return;
  }
  const PoseErrors errors = ComparePoses(result.cameras, truth);
  const double radius = RingRadius(truth);
  std::printf(
      "  registered %d of %zu; models %d; rotation error median %.3f max %.3f deg; "
      "position error median %.3f%% max %.3f%% of the ring radius (%.1f)\n",
      result.cameras.NumViews(), names.size(), result.num_models, Median(errors.rotation_degrees),
      Max(errors.rotation_degrees), 100 * Median(errors.position) / radius,
      100 * Max(errors.position) / radius, radius);
  agreement->AtMost("rotation error median vs the truth (deg)" + masks,
                    Median(errors.rotation_degrees), kMaxMedianRotationDeg);
  agreement->AtMost("position error median vs the truth (% of the ring radius)" + masks,
                    100 * Median(errors.position) / radius, kMaxMedianPositionPercent);
  CompareWorldFrames(result, truth, mattes, given, agreement);
}

int Run(const Settings& settings) {
  const std::vector<std::string> names = ChoosePhotos(settings);
  const ImageSet truth = ReadColmapModel(settings.truth);
  std::printf("%zu photos from %s; truth %s (%d views)\n", names.size(), settings.photos.c_str(),
              settings.truth.c_str(), truth.NumViews());
  const auto start = std::chrono::steady_clock::now();
  const std::vector<FloatImage> mattes = MakeMattes(truth, settings.photos);
  std::printf("mattes of %d views: %.2f s\n", truth.NumViews(), Seconds(start));
  const WorldFrame given = RunWorldFrame(truth, mattes);
  if (settings.world_frame_only) return 0;
  Agreement agreement("the truth");
  if (settings.masks == "0" || settings.masks == "both") {
    RunOnce(settings, false, names, truth, mattes, given, &agreement);
  }
  if (settings.masks == "1" || settings.masks == "both") {
    RunOnce(settings, true, names, truth, mattes, given, &agreement);
  }
  return agreement.ExitCode();
}

int Main(int argc, char** argv) {
  Settings settings;
  settings.colmap.num_threads = 2;
  if (argc == 2 && std::strcmp(argv[1], "--quick") == 0) {
    const fs::path dataset = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "romi-real-plant-24";
    settings.photos = dataset / "images";
    settings.truth = dataset / "colmap";
    settings.workspace = fs::temp_directory_path() / "sylva_registration_benchmark_quick";
    settings.first = 6;
    settings.colmap.max_image_size = 640;
    const int status = Run(settings);
    fs::remove_all(settings.workspace);
    return status;
  }
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const size_t equals = flag.find('=');
    const bool ok = flag.rfind("--", 0) == 0 &&
                    (equals != std::string::npos
                         ? ApplyFlag(flag.substr(2, equals - 2), flag.substr(equals + 1), &settings)
                         : ApplyFlag(flag.substr(2), "1", &settings));
    if (!ok) {
      std::fprintf(stderr, "unknown flag %s\n", flag.c_str());
      return 2;
    }
  }
  if (settings.photos.empty() || settings.truth.empty() || settings.workspace.empty()) {
    std::fprintf(stderr,
                 "usage: %s --photos=DIR --truth=MODEL_DIR --workspace=DIR [...] | --quick\n",
                 argv[0]);
    return 2;
  }
  return Run(settings);
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  try {
    return sylva::Main(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
}
