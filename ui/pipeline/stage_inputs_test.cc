// Stage keys hash exactly the inputs each stage declares (Pipeline::Inputs):
// changing any declared file or option makes the stage out of date.
#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/pipeline_test_util.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// A small project on a written synthetic dataset: 3 input views and one held
// out, mattes given (so the matte stage does not apply; a second project
// computes them).
class StageInputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sylva_stage_inputs_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    WriteTinySyntheticSet(dir_ / "data");
    // The photos without their alpha: the matte stage computes the mattes.
    fs::create_directories(dir_ / "rgb");
    for (const auto& entry : fs::directory_iterator(dir_ / "data" / "photos")) {
      const FloatImage rgba = ReadImage(entry.path());
      FloatImage rgb(rgba.width(), rgba.height(), 3);
      for (int y = 0; y < rgba.height(); ++y) {
        for (int x = 0; x < rgba.width(); ++x) {
          for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = rgba.at(x, y, c);
        }
      }
      WriteImage(dir_ / "rgb" / entry.path().filename(), rgb, PixelFormat::kUint8);
      // A photo of the backdrop alone: its corner colour everywhere.
      for (int y = 0; y < rgb.height(); ++y) {
        for (int x = 0; x < rgb.width(); ++x) {
          for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = rgba.at(0, 0, c);
        }
      }
      WriteImage(dir_ / "backdrop.png", rgb, PixelFormat::kUint8);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The project, with its cameras registered (the later stages' inputs are
  // known from them).
  Project MakeProject(const std::string& name, bool with_mattes,
                      const PipelineOptions& options = PipelineOptions()) const {
    ProjectSetup setup;
    setup.root = dir_ / name;
    setup.photos_dir = dir_ / (with_mattes ? "data/photos" : "rgb");
    setup.colmap_model_dir = dir_ / "data" / "colmap";
    if (with_mattes) setup.mattes_dir = dir_ / "data" / "mattes";
    setup.held_out = {"heldout_00.png"};
    setup.copy_inputs = true;
    Project project = Project::Create(setup);
    Pipeline(project, options, nullptr).Run(Stage::kRegister, false);
    return project;
  }

  fs::path dir_;
};

// Every declared file: touched in place (same content, a later modification
// time) or, if missing, created; the stage's key changes, and back.
void ExpectEveryFileMatters(const Project& project, const PipelineOptions& options) {
  const Pipeline pipeline(project, options, nullptr);
  for (const StageInfo& info : AllStages()) {
    const std::string before = pipeline.StageKey(info.stage);
    if (before == "not needed") continue;
    const StageInputs inputs = pipeline.Inputs(info.stage);
    EXPECT_FALSE(inputs.files.empty()) << info.name;
    for (const auto& [what, file] : inputs.files) {
      std::error_code ec;
      if (fs::exists(file, ec)) {
        const auto time = fs::last_write_time(file);
        fs::last_write_time(file, time + std::chrono::hours(1));
        EXPECT_NE(pipeline.StageKey(info.stage), before)
            << info.name << ": " << what << " " << file;
        fs::last_write_time(file, time);
      } else {
        fs::create_directories(file.parent_path());
        { std::ofstream(file) << "{}"; }
        EXPECT_NE(pipeline.StageKey(info.stage), before)
            << info.name << ": " << what << " " << file;
        fs::remove(file);
      }
      EXPECT_EQ(pipeline.StageKey(info.stage), before) << info.name << ": " << file << " restored";
    }
  }
}

TEST_F(StageInputsTest, EveryDeclaredFileChangesTheKey) {
  ExpectEveryFileMatters(MakeProject("given_mattes", true), PipelineOptions());
  PipelineOptions options;
  options.matte_stage.background_photo = (dir_ / "backdrop.png").string();
  ExpectEveryFileMatters(MakeProject("computed_mattes", false, options), options);
}

// The case that went stale (issue 13): the backdrop photo of
// Matting.trimap=difference replaced in place by another picture under the
// same name re-runs the matte stage.
TEST_F(StageInputsTest, ABackdropReplacedInPlaceReRunsTheMattes) {
  PipelineOptions options;
  const fs::path backdrop = dir_ / "backdrop.png";
  options.matte_stage.background_photo = backdrop.string();
  const Project project = MakeProject("backdrop_replaced", false, options);
  const Pipeline pipeline(project, options, nullptr);
  const std::string matte = pipeline.StageKey(Stage::kMatte);
  const auto time = fs::last_write_time(backdrop);
  FloatImage picture = ReadImage(backdrop);
  for (int c = 0; c < picture.channels(); ++c) picture.at(0, 0, c) = 1.0f - picture.at(0, 0, c);
  WriteImage(backdrop, picture, PixelFormat::kUint8);
  fs::last_write_time(backdrop, time + std::chrono::seconds(1));
  EXPECT_NE(pipeline.StageKey(Stage::kMatte), matte);
}

// A value of the same type that differs from `text` (not always valid).
std::string OtherValue(const OptionRegistry::Entry& entry, const std::string& text) {
  if (entry.type == "bool") return text == "true" ? "false" : "true";
  if (entry.type == "int" || entry.type == "uint64") return std::to_string(std::stoll(text) + 1);
  if (entry.type == "float") return FormatDouble(std::stod(text) * 1.1 + 0.01);
  return "";
}

// For each stage, each declared option section: some registered option of it
// changes the key when set to another valid value. And what a stage does not
// declare leaves its key alone.
TEST_F(StageInputsTest, DeclaredOptionsChangeTheKeyAndOthersDoNot) {
  const Project project = MakeProject("options", false);
  PipelineOptions defaults;
  OptionRegistry registry;
  RegisterPipelineOptions(&defaults, &registry);
  const Pipeline base(project, defaults, nullptr);
  for (const StageInfo& info : AllStages()) {
    const std::string before = base.StageKey(info.stage);
    ASSERT_NE(before, "not needed") << info.name;  // every stage applies here
    for (const std::string& prefix : base.Inputs(info.stage).options) {
      bool changed = false;
      for (const OptionRegistry::Entry& entry : registry.entries()) {
        if (changed || entry.key.rfind(prefix, 0) != 0) continue;
        const std::string other = OtherValue(entry, registry.Get(entry.key));
        if (other.empty()) continue;
        PipelineOptions options;
        OptionRegistry changed_registry;
        RegisterPipelineOptions(&options, &changed_registry);
        try {
          changed_registry.Set(entry.key, other, "test");
          const Pipeline pipeline(project, options, nullptr);
          EXPECT_NE(pipeline.StageKey(info.stage), before) << info.name << ": " << entry.key;
          changed = true;
        } catch (const InputError&) {
          // Not a valid value of this option; try the next one.
        }
      }
      EXPECT_TRUE(changed) << info.name << ": no option of " << prefix << " could be changed";
    }
  }
  // The report's options do not touch the density.
  PipelineOptions report;
  report.report.preview_size += 10;
  EXPECT_EQ(Pipeline(project, report, nullptr).StageKey(Stage::kDensity),
            base.StageKey(Stage::kDensity));
  EXPECT_NE(Pipeline(project, report, nullptr).StageKey(Stage::kReport),
            base.StageKey(Stage::kReport));
}

// A held-out view's matte is the report's input (and the register stage's,
// for the world frame), not the density's.
TEST_F(StageInputsTest, HeldOutMatteIsNotTheDensitys) {
  const Project project = MakeProject("held_out", true);
  const Pipeline pipeline(project, PipelineOptions(), nullptr);
  const fs::path matte = project.MattePath("heldout_00.png");
  const auto declares = [&](Stage stage) {
    for (const auto& file : pipeline.Inputs(stage).files) {
      if (file.second == matte) return true;
    }
    return false;
  };
  EXPECT_TRUE(declares(Stage::kRegister));
  EXPECT_FALSE(declares(Stage::kDensity));
  EXPECT_FALSE(declares(Stage::kSkeleton));
  EXPECT_TRUE(declares(Stage::kReport));
}

}  // namespace
}  // namespace sylva
