// Oracle tests of trees from drawings (issue 14): the synthetic generator's
// trees are known in 3D, so a drawing of one - its trunk and main branches
// projected into a view as strokes, its crown's outline as a closed crown
// stroke - is made into a tree by the sketch pipeline and compared with the
// truth: (a) the drawn branches are in the reconstructed skeleton seen from
// the drawing (2D distance from the strokes to the projected skeleton, in
// shares of the drawn height); (b) branching angles of the first order,
// median against the truth's; (c) the crown's depth / width against the
// truth's. With one drawing (the depth prior of a crown of revolution) and
// with two at right angles.
#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/camera_file.h"
#include "core/io/skeleton_io.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "mesh/tree_metrics.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/sketch_project.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// First-order branches at least this share of the tree's height long are
// drawn (a person draws the main branches, not every twig).
constexpr double kDrawnBranchShare = 0.15;

// The drawing a person would make of synthetic view `v`.
SketchDrawing DrawView(const SyntheticDataset& data, int v, const std::string& name) {
  const Camera& camera = data.image_set.CameraOf(v);
  SketchDrawing drawing;
  drawing.source = name;
  drawing.width = camera.width();
  drawing.height = camera.height();
  const SkeletonGraph& truth = data.tree.skeleton;
  double low = 1e300, high = -1e300;
  for (const SkeletonNode& node : truth.nodes) {
    low = std::min(low, node.position.z());
    high = std::max(high, node.position.z());
  }
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = truth.BranchAxes(&orders);
  for (size_t a = 0; a < axes.size(); ++a) {
    if (orders[a] > 1) continue;
    SketchStroke stroke;
    double length = 0.0;
    for (size_t i = 0; i < axes[a].size(); ++i) {
      const Eigen::Vector3d& p = truth.nodes[axes[a][i]].position;
      if (i > 0) length += (p - truth.nodes[axes[a][i - 1]].position).norm();
      Eigen::Vector2d pixel;
      data.image_set.Project(v, p, &pixel);
      if (stroke.points.empty() || (pixel - stroke.points.back()).norm() > 0.5) {
        stroke.points.push_back(pixel);
      }
    }
    if (orders[a] == 1 && length < kDrawnBranchShare * (high - low)) continue;
    if (stroke.points.size() >= 2) drawing.strokes.push_back(stroke);
  }
  // The crown: the outer contour of the matte.
  const FloatImage& matte = data.mattes[v];
  cv::Mat mask(matte.height(), matte.width(), CV_8U);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) mask.at<uchar>(y, x) = matte.at(x, y) > 0.5f ? 255 : 0;
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  const auto largest = std::max_element(
      contours.begin(), contours.end(),
      [](const auto& a, const auto& b) { return cv::contourArea(a) < cv::contourArea(b); });
  SketchStroke crown;
  crown.role = StrokeRole::kCrown;
  crown.closed = true;
  for (const cv::Point& p : *largest) crown.points.emplace_back(p.x + 0.5, p.y + 0.5);
  drawing.strokes.push_back(crown);
  Eigen::Vector2d root;
  data.image_set.Project(v, truth.nodes[0].position, &root);
  drawing.root = root;
  return drawing;
}

// Mean distance from the branch strokes' points to the nearest of `points`.
double MeanDistanceFromStrokes(const SketchDrawing& drawing,
                               const std::vector<Eigen::Vector2d>& points) {
  double sum = 0.0;
  int count = 0;
  for (const SketchStroke& stroke : drawing.strokes) {
    if (stroke.role != StrokeRole::kBranch) continue;
    for (const Eigen::Vector2d& p : stroke.points) {
      double nearest = 1e300;
      for (const Eigen::Vector2d& q : points) nearest = std::min(nearest, (p - q).squaredNorm());
      sum += std::sqrt(nearest);
      ++count;
    }
  }
  return sum / count;
}

// Horizontal extent of the skeleton's nodes along `axis`.
double Extent(const SkeletonGraph& skeleton, const Eigen::Vector3d& axis) {
  double low = 1e300, high = -1e300;
  for (const SkeletonNode& node : skeleton.nodes) {
    low = std::min(low, node.position.dot(axis));
    high = std::max(high, node.position.dot(axis));
  }
  return high - low;
}

double FirstOrderMedianAngle(const SkeletonGraph& skeleton) {
  const TreeMetricsReport metrics = ComputeTreeMetrics(skeleton, nullptr, "m");
  for (const auto& order : metrics.orders) {
    if (order.order == 1) return order.median_angle_deg;
  }
  return NAN;
}

struct OracleFigures {
  double stroke_distance_share = 0.0;                 // (a), of the drawn height
  double truth_angle = 0.0, angle = 0.0;              // (b), degrees
  double truth_depth_ratio = 0.0, depth_ratio = 0.0;  // (c)
};

// Draws `num_drawings` views of the synthetic tree of `seed`, makes the
// tree and measures it.
OracleFigures RunOracle(uint64_t seed, int num_drawings) {
  const fs::path dir =
      fs::temp_directory_path() / ("sylva_sketch_oracle_" + std::to_string(getpid()) + "_" +
                                   std::to_string(seed) + "_" + std::to_string(num_drawings));
  fs::remove_all(dir);
  SyntheticDatasetOptions synth;
  synth.seed = seed;
  synth.camera = SyntheticCameraKind::kOrthographic;
  synth.num_views = 2;
  synth.num_held_out = 0;
  synth.image_size = 256;
  synth.samples_per_axis = 1;
  const SyntheticDataset data = MakeSyntheticDataset(synth);
  std::vector<SketchDrawing> drawings;
  for (int v = 0; v < num_drawings; ++v) {
    drawings.push_back(DrawView(data, v, v == 0 ? "front.svg" : "side.svg"));
  }
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  SetSketchDefaults(&registry);
  registry.Set("Sketch.image_size", "256", "test");
  registry.Set("Density.resolution", "64", "test");
  registry.Set("Density.max_resolution", "64", "test");
  registry.Set("Report.previews", "false", "test");
  SketchSetup setup;
  setup.root = dir / "project";
  const Project project = CreateSketchProject(setup, drawings, options.sketch, registry);
  Pipeline(project, options, nullptr).Run(Stage::kSkeleton, false);
  const SkeletonGraph skeleton = ReadSkeletonJson(project.OutDir() / "skeleton.json");

  OracleFigures figures;
  const ImageSet cameras = ReadCameraFile(SketchCamerasPath(project));
  std::vector<Eigen::Vector2d> projected;
  for (const Eigen::Vector3d& p : skeleton.SamplePoints(0.01 * options.sketch.tree_height)) {
    Eigen::Vector2d pixel;
    cameras.Project(0, p, &pixel);
    projected.push_back(pixel);
  }
  const Eigen::Vector2d root = *drawings[0].root;
  double top = root.y();
  for (const SketchStroke& stroke : drawings[0].strokes) {
    for (const Eigen::Vector2d& p : stroke.points) top = std::min(top, p.y());
  }
  figures.stroke_distance_share =
      MeanDistanceFromStrokes(drawings[0], projected) / (root.y() - top);
  figures.truth_angle = FirstOrderMedianAngle(data.tree.skeleton);
  figures.angle = FirstOrderMedianAngle(skeleton);
  // Synthetic view 0 looks along -x with +y to its right; the sketch's
  // front view along +y with +x to its right.
  figures.truth_depth_ratio = Extent(data.tree.skeleton, Eigen::Vector3d::UnitX()) /
                              Extent(data.tree.skeleton, Eigen::Vector3d::UnitY());
  figures.depth_ratio =
      Extent(skeleton, Eigen::Vector3d::UnitY()) / Extent(skeleton, Eigen::Vector3d::UnitX());
  std::printf(
      "seed %d, %d drawing(s): strokes to skeleton %.2f %% of the height; first-order median "
      "angle %.1f (truth %.1f) deg; depth / width %.2f (truth %.2f)\n",
      static_cast<int>(seed), num_drawings, 100 * figures.stroke_distance_share, figures.angle,
      figures.truth_angle, figures.depth_ratio, figures.truth_depth_ratio);
  fs::remove_all(dir);
  return figures;
}

// Issue 14's figures: strokes within 1 % of the height, first-order median
// angle within 10 degrees, depth / width within 30 %. Measured (seeds 1, 2,
// the views' directions combined by DirectionField.combine=intersect, the
// sketch projects' default): 0.27 / 0.22 %; 42.7 / 37.7 against 39.0 / 41.1
// degrees; 1.17 / 1.24 against 1.03 / 1.15. The angle is the least stable
// figure: over seeds 1-6, one drawing or two, errors of -9.0 to +3.7
// degrees (mean 4.5; -14.0 to +3.4, mean 5.6, with 2 of the 12 beyond 10,
// before side branches of zipped stretches were zipped with them).
TEST(SketchOracleTest, OneDrawing) {
  for (uint64_t seed : {1, 2}) {
    const OracleFigures f = RunOracle(seed, 1);
    EXPECT_LT(f.stroke_distance_share, 0.01) << seed;
    EXPECT_NEAR(f.angle, f.truth_angle, 10.0) << seed;
    EXPECT_NEAR(f.depth_ratio / f.truth_depth_ratio, 1.0, 0.3) << seed;
  }
}

// Measured (seeds 1, 2): 0.20 / 0.21 %; 30.0 / 42.4 against 39.0 / 41.1
// degrees (25.0 for seed 1 before limbs traced beside the trunk were zipped
// with their side branches: their bundles ran down beside the trunk, so
// they left it at 6-12 degrees); 1.02 / 1.10 against 1.03 / 1.15.
TEST(SketchOracleTest, TwoDrawings) {
  for (uint64_t seed : {1, 2}) {
    const OracleFigures f = RunOracle(seed, 2);
    EXPECT_LT(f.stroke_distance_share, 0.01) << seed;
    EXPECT_NEAR(f.angle, f.truth_angle, 10.0) << seed;
    EXPECT_NEAR(f.depth_ratio / f.truth_depth_ratio, 1.0, 0.3) << seed;
  }
}

}  // namespace
}  // namespace sylva
