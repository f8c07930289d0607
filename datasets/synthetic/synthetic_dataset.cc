#include "datasets/synthetic/synthetic_dataset.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "core/io/camera_file.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "mesh/mesh_renderer.h"

namespace sylva {
namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int kCameraId = 1;
// Bisection steps when fitting the field of view under distortion.
constexpr int kBisectionSteps = 50;
// Points on each side of the square tested under distortion.
constexpr int kSquareBoundarySamples = 64;
// Under distortion, undistorted coordinates are kept below this many times
// the undistorted half field of view (the distortion may fold beyond it).
constexpr double kMaxUndistortedFraction = 1.5;
// Orthographic cameras sit this many bounding radii from the target (their
// position does not affect the image, only ProjectionCenter()).
constexpr double kOrthographicDistanceRadii = 3.0;

// A view to place: its photo name and direction from the target.
struct ViewSpec {
  std::string name;
  double azimuth_deg = 0.0;
  double elevation_deg = 0.0;
};

std::string ViewName(const char* prefix, int index) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%s_%02d.png", prefix, index);
  return buffer;
}

std::vector<ViewSpec> ViewSpecs(const SyntheticDatasetOptions& options) {
  const bool pinhole = options.camera == SyntheticCameraKind::kPinhole;
  const double step = (pinhole ? 360.0 : 180.0) / options.num_views;
  std::vector<ViewSpec> specs;
  for (int k = 0; k < options.num_views; ++k) {
    specs.push_back({ViewName("view", k), k * step, pinhole ? options.elevation_deg : 0.0});
  }
  // Held-out views half-way between input azimuths, spread over the ring.
  for (int j = 0; j < options.num_held_out; ++j) {
    const int k = j * options.num_views / options.num_held_out;
    specs.push_back({ViewName("heldout", j), (k + 0.5) * step, options.held_out_elevation_deg});
  }
  return specs;
}

// Unit vector from the target towards a camera at (azimuth, elevation).
Eigen::Vector3d DirectionToCamera(const ViewSpec& spec) {
  const double azimuth = spec.azimuth_deg * kDegree;
  const double elevation = spec.elevation_deg * kDegree;
  return Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                         std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

std::vector<Rigid3d> Poses(const std::vector<ViewSpec>& specs, const Eigen::Vector3d& target,
                           double distance) {
  std::vector<Rigid3d> poses;
  for (const ViewSpec& spec : specs) {
    poses.push_back(
        LookAt(target + distance * DirectionToCamera(spec), target, Eigen::Vector3d::UnitZ()));
  }
  return poses;
}

Camera PinholeCamera(const SyntheticDatasetOptions& options) {
  const double half = 0.5 * options.image_size;
  const double focal = half / std::tan(0.5 * options.fov_deg * kDegree);
  if (options.radial_distortion != 0.0) {
    return Camera(CameraModel::kSimpleRadial, options.image_size, options.image_size,
                  {focal, half, half, options.radial_distortion});
  }
  return Camera::Pinhole(options.image_size, options.image_size, focal);
}

// True if the square [-t, t]^2 of undistorted normalized coordinates maps
// into the image with `margin_px` to spare (checked along its boundary, which
// bounds the image of the square for radial distortion).
bool SquareFitsInImage(const Camera& camera, double t, double margin_px) {
  for (int i = 0; i <= kSquareBoundarySamples; ++i) {
    const double s = t * (2.0 * i / kSquareBoundarySamples - 1.0);
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(s, -t), Eigen::Vector2d(s, t),
                                     Eigen::Vector2d(-t, s), Eigen::Vector2d(t, s)}) {
      const Eigen::Vector2d point_in_image = camera.ImgFromCam(p.homogeneous());
      if ((point_in_image.array() < margin_px).any() ||
          (point_in_image.array() > camera.width() - margin_px).any()) {
        return false;
      }
    }
  }
  return true;
}

// The largest t (by bisection) for which SquareFitsInImage holds; without
// distortion, exactly (half size - margin) / focal length.
double MaxNormalizedExtent(const Camera& camera, double margin_px) {
  const double undistorted = (0.5 * camera.width() - margin_px) / camera.FocalLengthX();
  double lo = 0.0, hi = kMaxUndistortedFraction * undistorted;
  if (SquareFitsInImage(camera, hi, margin_px)) return hi;
  for (int step = 0; step < kBisectionSteps; ++step) {
    const double middle = 0.5 * (lo + hi);
    (SquareFitsInImage(camera, middle, margin_px) ? lo : hi) = middle;
  }
  return lo;
}

// How a point set sits in the views: its largest lateral offset from the
// optical axis through the target, and the smallest camera distance at which
// every point lies within t of the axis in normalized coordinates (a point at
// depth D - c with lateral offset a needs D >= c + a / t).
struct ViewFit {
  double max_lateral = 0.0;
  double min_distance = 0.0;
};

ViewFit FitViews(const std::vector<ViewSpec>& specs, const std::vector<Eigen::Vector3f>& points,
                 const Eigen::Vector3d& target, double t) {
  ViewFit fit;
  for (const ViewSpec& spec : specs) {
    const Eigen::Vector3d to_camera = DirectionToCamera(spec);
    const Eigen::Quaterniond cam_from_world =
        LookAt(target + to_camera, target, Eigen::Vector3d::UnitZ()).rotation;
    for (const Eigen::Vector3f& point : points) {
      const Eigen::Vector3d offset = point.cast<double>() - target;
      const double lateral = (cam_from_world * offset).head<2>().cwiseAbs().maxCoeff();
      fit.max_lateral = std::max(fit.max_lateral, lateral);
      fit.min_distance = std::max(fit.min_distance, offset.dot(to_camera) + lateral / t);
    }
  }
  return fit;
}

ImageSet AssembleImageSet(const Camera& camera, const std::vector<ViewSpec>& specs,
                          const std::vector<Rigid3d>& poses) {
  ImageSet image_set;
  image_set.cameras.emplace(kCameraId, camera);
  for (size_t i = 0; i < specs.size(); ++i) {
    View view;
    view.image_id = static_cast<int>(i) + 1;
    view.name = specs[i].name;
    view.camera_id = kCameraId;
    view.cam_from_world = poses[i];
    image_set.views.push_back(view);
  }
  return image_set;
}

void CheckOption(bool ok, const char* name, const std::string& requirement) {
  SYLVA_CHECK_INPUT(ok, std::string("SyntheticDatasetOptions.") + name)
      << "must be " << requirement;
}

}  // namespace

std::string SyntheticCameraKindName(SyntheticCameraKind kind) {
  return kind == SyntheticCameraKind::kPinhole ? "pinhole" : "orthographic";
}

void SyntheticDatasetOptions::Check() const {
  CheckOption(num_views >= 1, "num_views", ">= 1");
  CheckOption(num_held_out >= 0, "num_held_out", ">= 0");
  CheckOption(image_size >= 8, "image_size", ">= 8 pixels");
  CheckOption(samples_per_axis >= 1, "samples_per_axis", ">= 1");
  CheckOption(std::abs(elevation_deg) < 90, "elevation_deg", "in (-90, 90) degrees");
  CheckOption(std::abs(held_out_elevation_deg) < 90, "held_out_elevation_deg",
              "in (-90, 90) degrees");
  CheckOption(fov_deg > 0 && fov_deg < 170, "fov_deg", "in (0, 170) degrees");
  CheckOption(margin >= 0 && margin < 0.9, "margin", "in [0, 0.9)");
  CheckOption(std::abs(radial_distortion) <= 0.5, "radial_distortion", "in [-0.5, 0.5]");
  CheckOption(radial_distortion == 0 || camera == SyntheticCameraKind::kPinhole,
              "radial_distortion", "0 for orthographic cameras");
  tree.Check();
}

bool SyntheticDataset::IsHeldOut(const std::string& name) const {
  return std::find(held_out.begin(), held_out.end(), name) != held_out.end();
}

std::vector<bool> SyntheticDataset::HeldOutFlags() const {
  std::vector<bool> flags;
  for (const View& view : image_set.views) flags.push_back(IsHeldOut(view.name));
  return flags;
}

ImageSet SyntheticDataset::InputImageSet() const {
  ImageSet inputs = image_set;
  inputs.views.clear();
  for (const View& view : image_set.views) {
    if (!IsHeldOut(view.name)) inputs.views.push_back(view);
  }
  return inputs;
}

std::vector<FloatImage> SyntheticDataset::InputMattes() const {
  std::vector<FloatImage> inputs;
  for (int v = 0; v < image_set.NumViews(); ++v) {
    if (!IsHeldOut(image_set.views[v].name)) inputs.push_back(mattes[v]);
  }
  return inputs;
}

ImageSet MakeSyntheticCameras(const SyntheticDatasetOptions& options, const TriangleMesh& mesh) {
  options.Check();
  SYLVA_CHECK(mesh.NumVertices() > 0) << "cannot place cameras around an empty mesh";
  const Box3d box = mesh.Bounds();
  const Eigen::Vector3d target = box.center();
  const std::vector<ViewSpec> specs = ViewSpecs(options);
  const double margin_px = options.margin * 0.5 * options.image_size;
  if (options.camera == SyntheticCameraKind::kPinhole) {
    const Camera camera = PinholeCamera(options);
    const double t = MaxNormalizedExtent(camera, margin_px);
    const double distance = FitViews(specs, mesh.vertices, target, t).min_distance;
    return AssembleImageSet(camera, specs, Poses(specs, target, distance));
  }
  const double lateral = FitViews(specs, mesh.vertices, target, 1.0).max_lateral;
  const double pixels_per_metre = (0.5 * options.image_size - margin_px) / std::max(lateral, 1e-9);
  const double distance = kOrthographicDistanceRadii * 0.5 * box.diagonal().norm();
  return AssembleImageSet(
      Camera::Orthographic(options.image_size, options.image_size, pixels_per_metre), specs,
      Poses(specs, target, distance));
}

SyntheticDataset MakeSyntheticDataset(const SyntheticDatasetOptions& options,
                                      ProgressReporter* progress) {
  options.Check();
  return RenderSyntheticDataset(GenerateSyntheticTree(options.tree, options.seed), options,
                                progress);
}

SyntheticDataset RenderSyntheticDataset(SyntheticTree tree, const SyntheticDatasetOptions& options,
                                        ProgressReporter* progress) {
  options.Check();
  ProgressTask task(progress, "synthetic dataset");
  SyntheticDataset dataset;
  dataset.tree = std::move(tree);
  dataset.image_set = MakeSyntheticCameras(options, dataset.tree.mesh);
  for (int i = options.num_views; i < dataset.image_set.NumViews(); ++i) {
    dataset.held_out.push_back(dataset.image_set.views[i].name);
  }
  const MeshRenderer renderer(dataset.tree.mesh);
  MeshRenderOptions render_options;
  render_options.samples_per_axis = options.samples_per_axis;
  // Ground truth by Embree's rays, as the datasets were always made: the
  // rasterized path agrees to a sample in 65,536 pixels, but the tests'
  // figures were measured on these pictures (and one sample moved seed 1's
  // crown base by a branch).
  render_options.method = MeshRenderMethod::kRayCast;
  for (int i = 0; i < dataset.image_set.NumViews(); ++i) {
    task.Update(static_cast<double>(i) / dataset.image_set.NumViews());
    const View& view = dataset.image_set.views[i];
    dataset.photos.push_back(
        renderer.RenderRgba(dataset.image_set.CameraOf(view), view.cam_from_world, render_options));
    dataset.mattes.push_back(dataset.photos.back().Channel(3));
  }
  task.Update(1.0);
  return dataset;
}

namespace {

Json TreeOptionsToJson(const SyntheticTreeOptions& o) {
  // Floats printed as their shortest decimal (0.36, not 0.36000001430511475).
  const auto color = [](const Eigen::Vector3f& c) {
    Json rgb = Json::array();
    for (int k = 0; k < 3; ++k) rgb.push_back(std::stod(std::to_string(c[k])));
    return rgb;
  };
  return {{"trunk_length", o.trunk_length},
          {"trunk_base_radius", o.trunk_base_radius},
          {"trunk_wobble", o.trunk_wobble},
          {"crown_base", o.crown_base},
          {"crown_top", o.crown_top},
          {"num_children", o.num_children},
          {"length_ratio", o.length_ratio},
          {"child_start", o.child_start},
          {"branch_angle_min_deg", o.branch_angle_min_deg},
          {"branch_angle_max_deg", o.branch_angle_max_deg},
          {"phyllotaxis_angle_deg", o.phyllotaxis_angle_deg},
          {"phyllotaxis_jitter_deg", o.phyllotaxis_jitter_deg},
          {"branch_wobble", o.branch_wobble},
          {"upward_tropism", o.upward_tropism},
          {"max_segment_length", o.max_segment_length},
          {"pipe_exponent", o.pipe_exponent},
          {"tip_length", o.tip_length},
          {"min_radius", o.min_radius},
          {"leaves_per_cluster", o.leaves_per_cluster},
          {"cluster_radius", o.cluster_radius},
          {"cluster_size_jitter", o.cluster_size_jitter},
          {"cluster_elongation", o.cluster_elongation},
          {"leaf_length_min", o.leaf_length_min},
          {"leaf_length_max", o.leaf_length_max},
          {"leaf_aspect", o.leaf_aspect},
          {"tube_edge_length", o.tube_edge_length},
          {"tube_min_sides", o.tube_min_sides},
          {"tube_max_sides", o.tube_max_sides},
          {"bark_color", color(o.bark_color)},
          {"leaf_color", color(o.leaf_color)}};
}

Json SynthJson(const SyntheticDataset& dataset, const SyntheticDatasetOptions& o) {
  const Json options = {{"seed", o.seed},
                        {"num_views", o.num_views},
                        {"num_held_out", o.num_held_out},
                        {"camera", SyntheticCameraKindName(o.camera)},
                        {"image_size", o.image_size},
                        {"samples_per_axis", o.samples_per_axis},
                        {"elevation_deg", o.elevation_deg},
                        {"held_out_elevation_deg", o.held_out_elevation_deg},
                        {"fov_deg", o.fov_deg},
                        {"margin", o.margin},
                        {"radial_distortion", o.radial_distortion},
                        {"tree", TreeOptionsToJson(o.tree)}};
  const Json counts = {{"views", dataset.image_set.NumViews()},
                       {"held_out", dataset.held_out.size()},
                       {"skeleton_nodes", dataset.tree.skeleton.NumNodes()},
                       {"mesh_vertices", dataset.tree.mesh.NumVertices()},
                       {"mesh_triangles", dataset.tree.mesh.NumTriangles()},
                       {"leaf_clusters", dataset.tree.num_clusters},
                       {"leaves", dataset.tree.num_leaves}};
  return {{"format", "sylva-synthetic"}, {"version", 1},       {"seed", o.seed},
          {"units", dataset.units},      {"options", options}, {"counts", counts}};
}

void PrepareOutputDir(const fs::path& out_dir) {
  std::error_code ec;
  if (fs::exists(out_dir, ec)) {
    SYLVA_CHECK_INPUT(fs::is_directory(out_dir, ec), out_dir.string()) << "is not a folder";
    SYLVA_CHECK_INPUT(fs::is_empty(out_dir, ec), out_dir.string())
        << "exists and is not empty; refusing to write a synthetic dataset into it";
  }
  fs::create_directories(out_dir);
}

void WriteImages(const SyntheticDataset& dataset, const fs::path& out_dir) {
  const int num_views = dataset.image_set.NumViews();
  SYLVA_CHECK(static_cast<int>(dataset.photos.size()) == num_views &&
              static_cast<int>(dataset.mattes.size()) == num_views)
      << "dataset has " << dataset.photos.size() << " photos and " << dataset.mattes.size()
      << " mattes for " << num_views << " views";
  fs::create_directories(out_dir / "photos");
  fs::create_directories(out_dir / "mattes");
  tbb::parallel_for(0, num_views, [&](int i) {
    const std::string& name = dataset.image_set.views[i].name;
    WriteImage(out_dir / "photos" / name, dataset.photos[i], PixelFormat::kUint8);
    WriteImage(out_dir / "mattes" / name, dataset.mattes[i], PixelFormat::kUint16);
  });
}

}  // namespace

void WriteSyntheticDataset(const SyntheticDataset& dataset, const SyntheticDatasetOptions& options,
                           const fs::path& out_dir) {
  PrepareOutputDir(out_dir);
  WriteImages(dataset, out_dir);
  if (options.camera == SyntheticCameraKind::kPinhole) {
    WriteColmapModelText(dataset.image_set, out_dir / "colmap");
  }
  WriteCameraFile(out_dir / "cameras.json", dataset.image_set, dataset.units);
  std::string held_out;
  for (const std::string& name : dataset.held_out) held_out += name + "\n";
  AtomicWriteString(out_dir / "held_out.txt", held_out);
  WriteSkeletonJson(out_dir / "ground_truth" / "skeleton.json", dataset.tree.skeleton,
                    dataset.units);
  WriteObj(out_dir / "ground_truth" / "tree.obj", dataset.tree.mesh);
  WriteJsonFile(out_dir / "synth.json", SynthJson(dataset, options));
}

}  // namespace sylva
