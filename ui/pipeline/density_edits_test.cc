// Density painted on the photos (edits/density/<photo>.png): painting
// opacity in where the tree has none grows density there, painting it out of
// the crown empties it, and only the density stage and what follows re-run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/io/image_io.h"
#include "core/io/vdb_io.h"
#include "core/util/warning.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/project.h"
#include "ui/pipeline/report.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// The opacity the grid holds within `radius` of `center` (world).
double OpacityNear(const DensityGrid& grid, const Eigen::Vector3d& center, double radius) {
  double sum = 0.0;
  grid.ForEachActive([&](const Eigen::Vector3i& ijk, float value) {
    if ((grid.WorldFromIndex(ijk.cast<double>()) - center).norm() <= radius) sum += value;
  });
  return sum;
}

// Paints, in every view of `cameras`, the disc a ball of `radius` at
// `center` projects to: alpha 1, grey `value` (1 add, 0 remove). Each
// photo's edit accumulates the balls painted on it.
class DensityPainter {
 public:
  DensityPainter(const Project& project, ImageSet cameras)
      : project_(project), cameras_(std::move(cameras)) {}

  // In every view, or in view `only` alone when it is >= 0.
  void PaintBall(const Eigen::Vector3d& center, double radius, float value, int only = -1) {
    for (int v = 0; v < cameras_.NumViews(); ++v) {
      if (only >= 0 && v != only) continue;
      const Camera& camera = cameras_.CameraOf(v);
      const fs::path path = project_.EditsDir() / "density" /
                            fs::path(cameras_.views[v].name).replace_extension(".png");
      FloatImage edit =
          fs::exists(path) ? ReadImage(path) : FloatImage(camera.width(), camera.height(), 4, 0.0f);
      Eigen::Vector2d middle, top;
      ASSERT_TRUE(cameras_.Project(v, center, &middle));
      ASSERT_TRUE(cameras_.Project(v, center + radius * Eigen::Vector3d::UnitZ(), &top));
      const double pixels = (top - middle).norm();
      for (int y = 0; y < edit.height(); ++y) {
        for (int x = 0; x < edit.width(); ++x) {
          if ((Eigen::Vector2d(x + 0.5, y + 0.5) - middle).norm() > pixels) continue;
          for (int c = 0; c < 3; ++c) edit.at(x, y, c) = value;
          edit.at(x, y, 3) = 1.0f;
        }
      }
      fs::create_directories(path.parent_path());
      WriteImage(path, edit, PixelFormat::kUint8);
    }
  }

 private:
  const Project& project_;
  const ImageSet cameras_;
};

// A project of 6 synthetic views at 128 px, its density on a 48-voxel grid.
class DensityEditsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sylva_density_edits_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    SyntheticDatasetOptions synth;
    synth.num_views = 6;
    synth.num_held_out = 0;
    synth.image_size = 128;
    synth.samples_per_axis = 1;
    WriteSyntheticDataset(MakeSyntheticDataset(synth), synth, dir_ / "data");
    ProjectSetup setup;
    setup.root = dir_ / "project";
    setup.photos_dir = dir_ / "data" / "photos";
    setup.colmap_model_dir = dir_ / "data" / "colmap";
    setup.mattes_dir = dir_ / "data" / "mattes";
    project_ = std::make_unique<Project>(Project::Create(setup));
    options_.density.resolution = 48;
    options_.density.max_resolution = 48;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs the pipeline up to the density; returns the density stage's run.
  StageRun RunDensity() {
    const RunSummary summary = Pipeline(*project_, options_, nullptr).Run(Stage::kDensity, false);
    return summary.stages.back();
  }
  DensityGrid ReadDensity() const { return ReadDensityGrid(project_->OutDir() / "density.vdb"); }

  // A ball low beside the trunk of `grid`'s tree (empty: the crown starts at
  // 30 % of the height): its centre, and its radius in `radius`.
  static Eigen::Vector3d EmptyBall(const DensityGrid& grid, double* radius) {
    const Box3d box = grid.ActiveWorldBounds();
    const Eigen::Vector3d size = box.sizes();
    *radius = 0.08 * size.z();
    return {box.min().x() + 0.2 * size.x(), box.center().y(), box.min().z() + 0.12 * size.z()};
  }

  fs::path dir_;
  std::unique_ptr<Project> project_;
  PipelineOptions options_;
};

TEST_F(DensityEditsTest, PaintingAddsAndRemovesDensityAndReRunsFromTheDensity) {
  const Project& project = *project_;
  const PipelineOptions& options = options_;
  RunDensity();
  const DensityGrid before = ReadDensity();

  // A ball low beside the trunk and one in the middle of the crown, in the
  // world frame.
  double radius = 0.0;
  const Eigen::Vector3d empty = EmptyBall(before, &radius);
  const Box3d box = before.ActiveWorldBounds();
  const Eigen::Vector3d size = box.sizes();
  const Eigen::Vector3d crown(box.center().x(), box.center().y(), box.min().z() + 0.65 * size.z());
  const double empty_before = OpacityNear(before, empty, radius);
  const double crown_before = OpacityNear(before, crown, radius);
  ASSERT_GT(crown_before, 0.5) << "the crown holds density";

  const Pipeline pipeline(project, options, nullptr);
  const std::string register_key = pipeline.StageKey(Stage::kRegister);
  const std::string density_key = pipeline.StageKey(Stage::kDensity);
  const std::string skeleton_key = pipeline.StageKey(Stage::kSkeleton);
  DensityPainter painter(project, project.LoadCameras());
  painter.PaintBall(empty, radius, 1.0f);
  painter.PaintBall(crown, radius, 0.0f);
  EXPECT_EQ(pipeline.StageKey(Stage::kRegister), register_key) << "nothing before the density";
  EXPECT_NE(pipeline.StageKey(Stage::kDensity), density_key);
  EXPECT_NE(pipeline.StageKey(Stage::kSkeleton), skeleton_key) << "what follows re-runs too";

  RunDensity();
  const DensityGrid after = ReadDensity();
  const double empty_after = OpacityNear(after, empty, radius);
  const double crown_after = OpacityNear(after, crown, radius);
  std::printf("painted in: %.3f -> %.3f; painted out of the crown: %.3f -> %.3f\n", empty_before,
              empty_after, crown_before, crown_after);
  EXPECT_GT(empty_after, empty_before + 1.0);
  EXPECT_LT(crown_after, 0.2 * crown_before);
}

// A large edit in one view alone disagrees with the other views, but it is
// the person's word: the view-consensus test keeps that view (and says so)
// instead of leaving it, and the edit, out of the density.
TEST_F(DensityEditsTest, AViewWithALargeEditIsKeptAgainstTheOthers) {
  const StageRun clean = RunDensity();
  EXPECT_EQ(clean.Figure("distrusted_views"), 0.0);
  const DensityGrid before = ReadDensity();
  const Box3d box = before.ActiveWorldBounds();
  const Eigen::Vector3d crown = box.center() + 0.15 * box.sizes().z() * Eigen::Vector3d::UnitZ();
  const double radius = 0.25 * box.sizes().z();
  const double crown_before = OpacityNear(before, crown, 0.3 * radius);
  ASSERT_GT(crown_before, 0.5) << "the crown holds density";

  const ImageSet cameras = project_->LoadCameras();
  DensityPainter(*project_, cameras).PaintBall(crown, radius, 0.0f, /*only=*/0);
  const StageRun edited = RunDensity();
  const double crown_after = OpacityNear(ReadDensity(), crown, 0.3 * radius);
  std::printf("crown painted out in one view: %.3f -> %.3f\n", crown_before, crown_after);
  EXPECT_EQ(edited.Figure("distrusted_views"), 0.0);
  int kept = 0;
  for (const Warning& warning : edited.warnings) {
    if (warning.code == "edited-view-kept" && warning.subject == cameras.views[0].name) ++kept;
  }
  EXPECT_EQ(kept, 1) << "the summary says the disagreeing edited view was kept";
  EXPECT_LT(crown_after, 0.2 * crown_before) << "the edit carves the crown";

  // Without the exemption the painted view would have been left out.
  std::vector<FloatImage> mattes;
  for (int v = 0; v < cameras.NumViews(); ++v)
    mattes.push_back(project_->LoadEditedMatte(cameras, v));
  DensitySummary plain;
  ReconstructDensity(cameras, mattes, options_.density, nullptr, &plain);
  EXPECT_EQ(plain.distrusted_views, std::vector<std::string>{cameras.views[0].name});
}

// The app's loop (issue 18): after a density edit in one view, the density
// solve starts from the last one (cache/density_warm_start.bin) and stops
// sooner, and the attract stage traces that view alone; a forced run starts
// cold and traces every view, and finds the same density.
TEST_F(DensityEditsTest, ARunAfterAnEditStartsFromTheLastOne) {
  options_.density.warm_start = true;  // off by default (same inputs, same tree)
  const auto run = [&](bool force) {
    std::map<Stage, StageRun> runs;
    for (const StageRun& stage :
         Pipeline(*project_, options_, nullptr).Run(Stage::kAttract, force).stages) {
      runs[stage.stage] = stage;
    }
    return runs;
  };
  std::map<Stage, StageRun> first = run(false);
  EXPECT_EQ(first[Stage::kDensity].Figure("warm_voxels"), 0.0);
  EXPECT_EQ(first[Stage::kAttract].Figure("traced"), 6.0);
  const DensityGrid before = ReadDensity();
  const Box3d box = before.ActiveWorldBounds();
  const Eigen::Vector3d crown = box.center() + 0.15 * box.sizes().z() * Eigen::Vector3d::UnitZ();
  DensityPainter(*project_, project_->LoadCameras())
      .PaintBall(crown, 0.1 * box.sizes().z(), 0.0f, 0);

  std::map<Stage, StageRun> warm = run(false);
  const DensityGrid warm_grid = ReadDensity();
  std::map<Stage, StageRun> cold = run(true);
  const DensityGrid cold_grid = ReadDensity();
  const double warm_iterations = *warm[Stage::kDensity].Figure("iterations");
  const double cold_iterations = *cold[Stage::kDensity].Figure("iterations");
  std::printf("after the edit: warm %.0f iterations, cold %.0f\n", warm_iterations,
              cold_iterations);
  EXPECT_GT(warm[Stage::kDensity].Figure("warm_voxels"), 0.0);
  EXPECT_LT(warm_iterations, 0.5 * cold_iterations);
  EXPECT_EQ(cold[Stage::kDensity].Figure("warm_voxels"), 0.0);
  EXPECT_EQ(warm[Stage::kAttract].Figure("traced"), 1.0) << "only the edited view";
  EXPECT_EQ(cold[Stage::kAttract].Figure("traced"), 6.0);
  // The same fit to the edited mattes: the report's density IoU (the cold
  // solve stops after its iterations too, so voxel values differ a little).
  const ImageSet cameras = project_->LoadCameras();
  std::vector<FloatImage> mattes;
  for (int v = 0; v < cameras.NumViews(); ++v) {
    mattes.push_back(project_->LoadEditedMatte(cameras, v));
  }
  const std::vector<bool> held_out(cameras.NumViews(), false);
  const FidelityReport warm_fit =
      ComputeFidelity(warm_grid, cameras, mattes, held_out, options_.report);
  const FidelityReport cold_fit =
      ComputeFidelity(cold_grid, cameras, mattes, held_out, options_.report);
  std::printf("density IoU: warm %.4f, cold %.4f\n", *warm_fit.input.mean_iou,
              *cold_fit.input.mean_iou);
  EXPECT_GT(*warm_fit.input.mean_iou, *cold_fit.input.mean_iou - 0.005);
}

// A crown outline drawn over each photo (edits/<photo>.crown.svg, issue 14's
// editors on photos) where the tree has none fills the matte there: the
// density grows inside, and the density re-runs.
TEST_F(DensityEditsTest, CrownOutlinesDrawnOverThePhotosAddDensity) {
  RunDensity();
  const DensityGrid before = ReadDensity();
  double radius = 0.0;
  const Eigen::Vector3d empty = EmptyBall(before, &radius);
  const double empty_before = OpacityNear(before, empty, radius);
  const Pipeline pipeline(*project_, options_, nullptr);
  const std::string density_key = pipeline.StageKey(Stage::kDensity);
  const ImageSet cameras = project_->LoadCameras();
  for (int v = 0; v < cameras.NumViews(); ++v) {
    Eigen::Vector2d middle, top;
    ASSERT_TRUE(cameras.Project(v, empty, &middle));
    ASSERT_TRUE(cameras.Project(v, empty + radius * Eigen::Vector3d::UnitZ(), &top));
    const Camera& camera = cameras.CameraOf(v);
    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << camera.width() << "\" height=\""
        << camera.height() << "\"><circle cx=\"" << middle.x() << "\" cy=\"" << middle.y()
        << "\" r=\"" << (top - middle).norm() << "\"/></svg>";
    const fs::path path =
        project_->EditsDir() /
        (fs::path(cameras.views[v].name).replace_extension().string() + ".crown.svg");
    std::ofstream(path) << svg.str();
    EXPECT_EQ(project_->CrownEditPath(cameras.views[v].name), path);
  }
  EXPECT_NE(pipeline.StageKey(Stage::kDensity), density_key);
  RunDensity();
  const double empty_after = OpacityNear(ReadDensity(), empty, radius);
  std::printf("crown outlined: %.3f -> %.3f\n", empty_before, empty_after);
  EXPECT_GT(empty_after, empty_before + 1.0);
}

}  // namespace
}  // namespace sylva
