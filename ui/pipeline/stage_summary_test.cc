// Stage summaries as figures (StageRun::figures): filled by the stages,
// printed by the CLI's run summary, kept for up-to-date stages.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/io/json_util.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/pipeline_test_util.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A project on a written synthetic dataset: 3 input views, one held out,
// mattes given.
class StageSummaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sylva_stage_summary_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    WriteTinySyntheticSet(dir_ / "data");
    ProjectSetup setup;
    setup.root = dir_ / "project";
    setup.photos_dir = dir_ / "data" / "photos";
    setup.colmap_model_dir = dir_ / "data" / "colmap";
    setup.mattes_dir = dir_ / "data" / "mattes";
    setup.held_out = {"heldout_00.png"};
    project_ = std::make_unique<Project>(Project::Create(setup));
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::unique_ptr<Project> project_;
};

TEST_F(StageSummaryTest, StagesReportFiguresThatUpToDateRunsKeep) {
  PipelineOptions options;
  options.density.resolution = 24;
  RunSummary first = Pipeline(*project_, options, nullptr).Run(Stage::kDensity, false);
  ASSERT_EQ(first.stages.size(), 2u);
  const StageRun& registered = first.stages[0];
  EXPECT_EQ(registered.Figure("photos"), 4.0);
  EXPECT_EQ(registered.Figure("registered"), 4.0);
  EXPECT_EQ(registered.Figure("unregistered"), 0.0);
  ASSERT_TRUE(registered.Figure("seconds"));
  EXPECT_EQ(*registered.Figure("seconds"), registered.seconds);
  const StageRun& density = first.stages[1];
  EXPECT_EQ(density.Figure("views"), 3.0);  // the held-out view is not used
  ASSERT_TRUE(density.Figure("stored_voxels"));
  EXPECT_GT(*density.Figure("stored_voxels"), 0.0);
  EXPECT_FALSE(density.Figure("no such figure"));
  EXPECT_TRUE(Contains(first.BriefReport(),
                       "  figures: photos=4 photos, registered=4 photos, unregistered=0 photos, "
                       "seconds="))
      << first.BriefReport();

  // Up to date: the same figures, as recorded.
  const RunSummary again = Pipeline(*project_, options, nullptr).Run(Stage::kDensity, false);
  ASSERT_EQ(again.stages.size(), 2u);
  for (size_t s = 0; s < 2; ++s) {
    EXPECT_TRUE(again.stages[s].up_to_date);
    EXPECT_EQ(FiguresText(again.stages[s].figures), FiguresText(first.stages[s].figures));
  }
}

// The first step named `name` in a profile's JSON list (null if none).
Json FindStep(const Json& steps, const std::string& name) {
  for (const Json& step : steps) {
    if (step.value("name", "") == name) return step;
  }
  return nullptr;
}

TEST_F(StageSummaryTest, EveryRunWritesItsProfileStepByStep) {
  PipelineOptions options;
  options.density.resolution = 24;
  const RunSummary first = Pipeline(*project_, options, nullptr).Run(Stage::kDensity, false);
  ASSERT_EQ(first.stages.size(), 2u);
  const StageRun& density = first.stages[1];
  ASSERT_FALSE(density.profile.empty());
  double sum = 0.0;
  for (const StageStep& step : density.profile) sum += step.seconds;
  EXPECT_LE(sum, density.seconds + 1e-6);  // the steps are inside the stage's time
  EXPECT_GT(sum, 0.5 * density.seconds);   // and account for most of it
  EXPECT_TRUE(Contains(first.BriefReport(), "  time: read_mattes ")) << first.BriefReport();

  // out/run.json: every stage with its steps, and the reconstruction's own
  // steps inside its step; cache/stages.json keeps the steps per stage.
  const Json run = ReadJsonFile(project_->OutDir() / "run.json");
  ASSERT_TRUE(run.contains("profile"));
  const Json& stages = run["profile"]["stages"];
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[1]["stage"], "density");
  EXPECT_EQ(stages[1]["up_to_date"], false);
  const Json reconstruct = FindStep(stages[1]["steps"], "reconstruct");
  ASSERT_TRUE(reconstruct.is_object());
  EXPECT_TRUE(FindStep(reconstruct["steps"], "solve").is_object());
  EXPECT_NEAR(run["profile"]["seconds"].get<double>(), first.stages[0].seconds + density.seconds,
              1e-9);
  const Json records = ReadJsonFile(project_->CacheDir() / "stages.json");
  EXPECT_TRUE(FindStep(records["density"]["profile"], "write").is_object());

  // Up to date: no time spent, no steps.
  Pipeline(*project_, options, nullptr).Run(Stage::kDensity, false);
  const Json again = ReadJsonFile(project_->OutDir() / "run.json");
  EXPECT_EQ(again["profile"]["seconds"].get<double>(), 0.0);
  EXPECT_EQ(again["profile"]["stages"][1]["up_to_date"], true);
  EXPECT_TRUE(again["profile"]["stages"][1]["steps"].empty());
}

TEST(StageFiguresTest, TextShowsCountsWholeAndOtherValuesShort) {
  StageRun run;
  EXPECT_EQ(FiguresText(run.figures), "");
  run.AddFigure("voxels", 5094241, "voxels");
  run.AddFigure("mean_iou", 0.95123456);
  run.AddFigure("seconds", 12.3456, "s");
  EXPECT_EQ(FiguresText(run.figures), "voxels=5094241 voxels, mean_iou=0.9512, seconds=12.35 s");
}

TEST(StageProfileTest, TextListsStepsWithTheirSubSteps) {
  std::vector<StageStep> profile;
  EXPECT_EQ(ProfileText(profile), "");
  profile.push_back({"read", 0.125, {}});
  profile.push_back({"solve", 2.0, {}});
  profile.back().Add("init", 0.5).Add("iterate", 1.25);
  EXPECT_EQ(ProfileText(profile), "read 0.125 s, solve 2 s (init 0.5, iterate 1.25)");
}

// The report keeps the density's projections (cache/report_projections.bin):
// a run in which only the mesh changed reuses them and reports the same
// density figures; a forced run, a new density or a damaged file projects
// again. A run in which the density and the report both run makes them
// beside the stages in between (projections_made_before), with the same
// figures as the report makes them alone.
TEST_F(StageSummaryTest, TheReportReusesTheDensityProjectionsWhileTheDensityHolds) {
  PipelineOptions options;
  options.density.resolution = 24;
  const auto report = [&](const PipelineOptions& with, bool force) {
    return Pipeline(*project_, with, nullptr).Run(Stage::kReport, force).stages.back();
  };
  const StageRun first = report(options, false);
  ASSERT_EQ(first.stage, Stage::kReport);
  EXPECT_EQ(first.Figure("reused_projections"), 0.0);
  EXPECT_EQ(first.Figure("projections_made_before"), 4.0);
  PipelineOptions other_mesh = options;
  other_mesh.leaves.leaf_aspect = 0.5;
  const StageRun second = report(other_mesh, false);
  EXPECT_EQ(second.Figure("reused_projections"), 4.0);
  EXPECT_EQ(second.Figure("projections_made_before"), 0.0);
  for (const char* figure : {"input_mean_iou", "held_out_mean_iou"}) {
    ASSERT_TRUE(first.Figure(figure)) << figure;
    EXPECT_EQ(second.Figure(figure), first.Figure(figure)) << figure;
  }
  EXPECT_NE(second.Figure("mesh_input_mean_iou"), std::nullopt);
  const StageRun forced = report(options, true);  // cold: nothing of an earlier run
  EXPECT_EQ(forced.Figure("reused_projections"), 0.0);
  EXPECT_EQ(forced.Figure("projections_made_before"), 4.0);
  // The report stage alone (nothing runs before it, no cache) projects itself.
  fs::remove(project_->CacheDir() / "report_projections.bin");
  const StageRun alone = Pipeline(*project_, options, nullptr).RunStage(Stage::kReport);
  EXPECT_EQ(alone.Figure("projections_made_before"), 0.0);
  EXPECT_EQ(alone.Figure("reused_projections"), 0.0);
  for (const char* figure : {"input_mean_iou", "held_out_mean_iou"}) {
    EXPECT_EQ(forced.Figure(figure), first.Figure(figure)) << figure;
    EXPECT_EQ(alone.Figure(figure), first.Figure(figure)) << figure;
  }
  const fs::path cache = project_->CacheDir() / "report_projections.bin";
  ASSERT_TRUE(fs::is_regular_file(cache));
  const auto size = fs::file_size(cache);
  fs::resize_file(cache, size - 7);
  const StageRun damaged = report(other_mesh, false);
  EXPECT_EQ(damaged.Figure("reused_projections"), 0.0);
  EXPECT_EQ(damaged.Figure("input_mean_iou"), first.Figure("input_mean_iou"));
  EXPECT_EQ(fs::file_size(cache), size);  // written again
  PipelineOptions other_density = other_mesh;
  other_density.density.resolution = 28;
  const StageRun new_density = report(other_density, false);
  ASSERT_EQ(new_density.stage, Stage::kReport) << new_density.brief;
  EXPECT_EQ(new_density.Figure("reused_projections"), 0.0);
  EXPECT_EQ(new_density.Figure("projections_made_before"), 4.0);
}

}  // namespace
}  // namespace sylva
