#include "reconstruct/registration/colmap_runner.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <thread>

#include "core/geometry/sim3.h"
#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/util/file_util.h"
#include "reconstruct/registration/registration_test_util.h"

namespace sylva {
namespace {

const fs::path kDataset = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "romi-real-plant-24";
// The ROMI scanner's camera ring radius (PROVENANCE.md), mm.
constexpr double kRingRadiusMm = 350.0;

// A fresh folder for one test, removed afterwards.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("sylva_colmap_test_" + std::to_string(getpid()) + "_" + name)) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    if (!std::getenv("SYLVA_KEEP_SCRATCH")) fs::remove_all(path_);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::vector<std::string> DatasetPhotos(int first, int count) {
  const std::vector<std::string> names = SortedFileNames(kDataset / "images");
  return std::vector<std::string>(names.begin() + first, names.begin() + first + count);
}

ColmapOptions FastOptions() {
  ColmapOptions options;
  options.executable = "colmap";  // found in PATH (Debian: /usr/bin/colmap)
  options.max_image_size = 640;
  options.num_threads = 2;
  return options;
}

// Records every progress report; optionally asks to cancel at the first.
class RecordingProgress : public ProgressReporter {
 public:
  explicit RecordingProgress(bool cancel_at_first = false) : cancel_at_first_(cancel_at_first) {}
  void Update(std::string_view task, double fraction) override {
    tasks.emplace_back(task);
    fractions.push_back(fraction);
    if (cancel_at_first_) RequestCancel();
  }
  std::vector<std::string> tasks;
  std::vector<double> fractions;

 private:
  bool cancel_at_first_;
};

TEST(ColmapOptionsTest, CheckNamesTheBadField) {
  EXPECT_NO_THROW(ColmapOptions().Check());
  const auto expect_bad = [](const std::string& field, auto change) {
    ColmapOptions options;
    change(&options);
    try {
      options.Check();
      ADD_FAILURE() << field << " accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), "Colmap." + field);
    }
  };
  expect_bad("matcher", [](ColmapOptions* o) { o->matcher = "vocab_tree"; });
  expect_bad("camera_model", [](ColmapOptions* o) { o->camera_model = "ORTHOGRAPHIC"; });
  expect_bad("max_image_size", [](ColmapOptions* o) { o->max_image_size = 10; });
  expect_bad("num_threads", [](ColmapOptions* o) { o->num_threads = 0; });
  expect_bad("exhaustive_max_photos", [](ColmapOptions* o) { o->exhaustive_max_photos = 1; });
  expect_bad("executable", [](ColmapOptions* o) { o->executable = ""; });
  expect_bad("stall_seconds", [](ColmapOptions* o) { o->stall_seconds = -1; });
}

TEST(ColmapMaskTest, DilatesTheThresholdedMatte) {
  FloatImage matte(20, 10, 1, 0.0f);
  matte.at(5, 5) = 0.9f;
  matte.at(15, 2) = 0.4f;  // below the threshold
  const FloatImage mask = ColmapMaskFromMatte(matte, 0.5f, 2);
  int on = 0;
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 20; ++x) {
      const bool inside = std::abs(x - 5) <= 2 && std::abs(y - 5) <= 2;
      EXPECT_EQ(mask.at(x, y), inside ? 1.0f : 0.0f) << x << "," << y;
      on += mask.at(x, y) > 0;
    }
  }
  EXPECT_EQ(on, 25);
  EXPECT_EQ(ColmapMaskPath("masks", "side/30.jpg"), fs::path("masks/side/30.jpg.png"));
}

TEST(ColmapRunnerTest, MissingExecutableIsAnInputError) {
  ScratchDir scratch("missing");
  for (const char* executable : {"/nonexistent/bin/colmap", "colmap-not-installed-here"}) {
    ColmapOptions options = FastOptions();
    options.executable = executable;
    try {
      RunColmap(kDataset / "images", DatasetPhotos(0, 2), "", scratch.path(), options, nullptr);
      ADD_FAILURE() << "no error for " << executable;
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), "Colmap.executable");
      EXPECT_NE(error.message().find("colmap not found"), std::string::npos) << error.what();
      EXPECT_NE(error.message().find("Debian package colmap"), std::string::npos);
    }
  }
}

TEST(ColmapRunnerTest, BadPhotosAreInputErrors) {
  ScratchDir scratch("bad_photos");
  const ColmapOptions options = FastOptions();
  EXPECT_THROW(RunColmap(scratch.path() / "no_such_folder", {"a.jpg"}, "", scratch.path() / "ws",
                         options, nullptr),
               InputError);
  EXPECT_THROW(RunColmap(kDataset / "images", {}, "", scratch.path() / "ws", options, nullptr),
               InputError);
  // Names must stay inside the photo folder.
  for (const std::string& name : {std::string("../x.jpg"), std::string("/etc/passwd")}) {
    EXPECT_THROW(
        RunColmap(kDataset / "images", {name}, "", scratch.path() / "ws", options, nullptr),
        InputError)
        << name;
  }
  // An empty file where a photo should be: named in the error.
  fs::create_directories(scratch.path() / "photos");
  AtomicWriteString(scratch.path() / "photos" / "empty.jpg", "");
  try {
    RunColmap(scratch.path() / "photos", {"empty.jpg"}, "", scratch.path() / "ws", options,
              nullptr);
    ADD_FAILURE() << "empty photo accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("empty.jpg"), std::string::npos) << error.what();
  }
  // Masks asked for but missing.
  ColmapOptions with_masks = options;
  with_masks.use_masks = true;
  EXPECT_THROW(RunColmap(kDataset / "images", DatasetPhotos(0, 2), scratch.path() / "masks",
                         scratch.path() / "ws", with_masks, nullptr),
               InputError);
}

TEST(ColmapRunnerTest, FailingColmapReportsExitCodeAndLog) {
  ScratchDir scratch("failing");
  ColmapOptions options = FastOptions();
  options.executable = "/bin/false";
  try {
    RunColmap(kDataset / "images", DatasetPhotos(0, 2), "", scratch.path(), options, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const RegistrationError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("feature_extractor failed with exit code 1"), std::string::npos)
        << message;
    EXPECT_NE(message.find((scratch.path() / "colmap.log").string()), std::string::npos);
    EXPECT_EQ(error.log_path(), scratch.path() / "colmap.log");
    EXPECT_TRUE(fs::exists(error.log_path()));
  }
}

// Real COLMAP on 8 consecutive ROMI photos (15 degrees apart): all register,
// and the poses agree with the scanner's COLMAP cameras up to a similarity.
TEST(ColmapRunnerTest, RegistersRealPhotosLikeTheGivenCameras) {
  ScratchDir scratch("real");
  const std::vector<std::string> names = DatasetPhotos(0, 8);
  RecordingProgress progress;
  const ColmapResult result =
      RunColmap(kDataset / "images", names, "", scratch.path(), FastOptions(), &progress);
  SCOPED_TRACE(result.BriefReport());
  EXPECT_EQ(result.cameras.NumViews(), 8);
  EXPECT_TRUE(result.unregistered.empty());
  EXPECT_EQ(result.num_models, 1);
  EXPECT_EQ(result.matcher, "exhaustive");
  EXPECT_TRUE(result.single_camera);
  EXPECT_EQ(result.cameras.cameras.size(), 1u);
  EXPECT_GT(result.cameras.points.size(), 100u);
  EXPECT_GT(result.extraction_seconds, 0);
  EXPECT_GT(result.matching_seconds, 0);
  EXPECT_GT(result.mapping_seconds, 0);
  EXPECT_NEAR(result.colmap_seconds,
              result.extraction_seconds + result.matching_seconds + result.mapping_seconds, 1e-9);
  EXPECT_LT(result.sylva_seconds, result.colmap_seconds);

  const ImageSet truth = ReadColmapModelText(kDataset / "colmap");
  const PoseErrors errors = ComparePoses(result.cameras, truth);
  std::cout << "8 ROMI photos: rotation error median " << Median(errors.rotation_degrees) << " max "
            << Max(errors.rotation_degrees) << " deg; position error median "
            << Median(errors.position) << " max " << Max(errors.position) << " mm\n";
  EXPECT_LT(Median(errors.rotation_degrees), 0.5);
  EXPECT_LT(Max(errors.rotation_degrees), 1.0);
  EXPECT_LT(Median(errors.position) / kRingRadiusMm, 0.01);
  EXPECT_LT(Max(errors.position) / kRingRadiusMm, 0.02);

  // Progress from each command, rising to the end.
  ASSERT_FALSE(progress.fractions.empty());
  std::string reports;
  for (size_t k = 0; k < progress.fractions.size(); ++k) {
    reports += progress.tasks[k] + " " + std::to_string(progress.fractions[k]) + "\n";
  }
  EXPECT_TRUE(std::is_sorted(progress.fractions.begin(), progress.fractions.end())) << reports;
  EXPECT_DOUBLE_EQ(progress.fractions.back(), 1.0);
  for (const char* task : {"register: COLMAP feature extraction", "register: COLMAP matching",
                           "register: COLMAP mapping"}) {
    EXPECT_NE(std::find(progress.tasks.begin(), progress.tasks.end(), task), progress.tasks.end())
        << task;
  }
  const std::string log = ReadFileToString(result.log_path);
  EXPECT_NE(log.find("Processed file [8/8]"), std::string::npos);
  EXPECT_NE(log.find("--SiftExtraction.use_gpu 0"), std::string::npos);
}

// Photos in sub-folders, with masks (COLMAP's naming: <mask dir>/<name>.png).
TEST(ColmapRunnerTest, RegistersPhotosInSubfoldersWithMasks) {
  ScratchDir scratch("masks");
  std::vector<std::string> names;
  const std::vector<std::string> originals = DatasetPhotos(8, 4);
  for (size_t i = 0; i < originals.size(); ++i) {
    const std::string name = (i < 2 ? "left/" : "right/") + originals[i];
    fs::create_directories((scratch.path() / "photos" / name).parent_path());
    fs::create_directories((scratch.path() / "masks" / name).parent_path());
    fs::copy_file(kDataset / "images" / originals[i], scratch.path() / "photos" / name);
    const FloatImage mask =
        ColmapMaskFromMatte(RomiMatte(ReadImage(kDataset / "images" / originals[i])), 0.5f, 8);
    WriteImage(ColmapMaskPath(scratch.path() / "masks", name), mask);
    names.push_back(name);
  }
  ColmapOptions options = FastOptions();
  options.use_masks = true;
  const ColmapResult result = RunColmap(scratch.path() / "photos", names, scratch.path() / "masks",
                                        scratch.path() / "ws", options, nullptr);
  SCOPED_TRACE(result.BriefReport());
  // The masks keep only the plant, pot and rod: far fewer features (these
  // photos give 900-1300 each without masks at this size), often too few to
  // register them all (ROMI's velvet folds and orange markers carry most of
  // the matches).
  const std::string log = ReadFileToString(result.log_path);
  EXPECT_NE(log.find("--ImageReader.mask_path"), std::string::npos);
  int photos_extracted = 0;
  for (size_t at = log.find("Features:"); at != std::string::npos;
       at = log.find("Features:", at + 1)) {
    EXPECT_LT(std::stoi(log.substr(at + 9)), 700);
    ++photos_extracted;
  }
  EXPECT_EQ(photos_extracted, 4);
  EXPECT_GE(result.cameras.NumViews(), 2);
  EXPECT_EQ(result.cameras.NumViews() + result.unregistered.size(), 4u);
  for (const View& view : result.cameras.views) {
    EXPECT_NE(std::find(names.begin(), names.end(), view.name), names.end()) << view.name;
  }
}

// One real photo and one without any texture: nothing to match.
TEST(ColmapRunnerTest, UnregistrablePhotosAreARegistrationError) {
  ScratchDir scratch("unregistrable");
  fs::create_directories(scratch.path() / "photos");
  const std::string photo = DatasetPhotos(0, 1).front();
  fs::copy_file(kDataset / "images" / photo, scratch.path() / "photos" / photo);
  WriteImage(scratch.path() / "photos" / "grey.png", FloatImage(1616, 1080, 3, 0.5f));
  for (const std::vector<std::string>& names :
       {std::vector<std::string>{photo}, std::vector<std::string>{photo, "grey.png"}}) {
    try {
      RunColmap(scratch.path() / "photos", names, "", scratch.path() / "ws", FastOptions(),
                nullptr);
      ADD_FAILURE() << names.size() << " photos registered";
    } catch (const RegistrationError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("no matches between the " + std::to_string(names.size()) + " photos"),
                std::string::npos)
          << message;
      EXPECT_NE(message.find("full log: "), std::string::npos);
    }
  }
}

TEST(ColmapRunnerTest, CancellingStopsRealColmapQuickly) {
  ScratchDir scratch("cancel_real");
  RecordingProgress progress(/*cancel_at_first=*/true);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(RunColmap(kDataset / "images", DatasetPhotos(0, 24), "", scratch.path(),
                         FastOptions(), &progress),
               Cancelled);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Extracting all 24 photos takes several times longer.
  EXPECT_LT(seconds, 5.0);
  ASSERT_FALSE(progress.tasks.empty());
  EXPECT_EQ(progress.tasks.front(), "register: COLMAP feature extraction");
}

// A stand-in "colmap" (a shell script) for outcomes the real one does not
// give on demand: every command succeeds, and the mapper copies the models
// in `models_dir` (if any) to its --output_path.
fs::path WriteStandIn(const fs::path& folder, const fs::path& models_dir) {
  const fs::path script = folder / "stand_in_colmap.sh";
  std::string text = "#!/bin/sh\ncommand=$1\nout=\n";
  text += "while [ $# -gt 0 ]; do [ \"$1\" = --output_path ] && out=$2; shift; done\n";
  if (!models_dir.empty()) {
    text += "[ \"$command\" = mapper ] && cp -r '" + models_dir.string() + "'/. \"$out\"/\n";
  }
  text += "echo \"stand-in $command\"\nexit 0\n";
  AtomicWriteString(script, text);
  fs::permissions(script, fs::perms::owner_all);
  return script;
}

// A COLMAP model of the given photos (poses are irrelevant here).
void WriteModel(const fs::path& folder, const std::vector<std::string>& names) {
  ImageSet model;
  model.cameras[1] = Camera(CameraModel::kSimpleRadial, 1616, 1080, {1100, 808, 540, 0});
  for (size_t i = 0; i < names.size(); ++i) {
    View view;
    view.image_id = static_cast<int>(i) + 1;
    view.name = names[i];
    view.camera_id = 1;
    view.cam_from_world.translation = Eigen::Vector3d(static_cast<double>(i), 0, 4);
    model.views.push_back(view);
  }
  WriteColmapModelText(model, folder);
}

TEST(ColmapRunnerTest, NoModelIsARegistrationError) {
  ScratchDir scratch("no_model");
  ColmapOptions options = FastOptions();
  options.executable = WriteStandIn(scratch.path(), "").string();
  try {
    RunColmap(kDataset / "images", DatasetPhotos(0, 3), "", scratch.path() / "ws", options,
              nullptr);
    ADD_FAILURE() << "no error";
  } catch (const RegistrationError& error) {
    EXPECT_NE(std::string(error.what()).find("COLMAP built no model"), std::string::npos)
        << error.what();
    EXPECT_EQ(error.source(), (kDataset / "images").string());
  }
}

TEST(ColmapRunnerTest, OnePhotoModelIsARegistrationError) {
  ScratchDir scratch("one_photo_model");
  const std::vector<std::string> names = DatasetPhotos(0, 3);
  WriteModel(scratch.path() / "models" / "0", {names[1]});
  ColmapOptions options = FastOptions();
  options.executable = WriteStandIn(scratch.path(), scratch.path() / "models").string();
  try {
    RunColmap(kDataset / "images", names, "", scratch.path() / "ws", options, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const RegistrationError& error) {
    EXPECT_NE(std::string(error.what()).find("registered only 1 of 3 photos"), std::string::npos)
        << error.what();
  }
}

// Several models: the largest is kept; the photos of the others, and those in
// none, are unregistered (in the order given).
TEST(ColmapRunnerTest, SeveralModelsKeepTheLargest) {
  ScratchDir scratch("several_models");
  const std::vector<std::string> names = DatasetPhotos(0, 6);
  WriteModel(scratch.path() / "models" / "0", {names[0], names[1]});
  WriteModel(scratch.path() / "models" / "1", {names[2], names[3], names[5]});
  ColmapOptions options = FastOptions();
  options.executable = WriteStandIn(scratch.path(), scratch.path() / "models").string();
  const ColmapResult result =
      RunColmap(kDataset / "images", names, "", scratch.path() / "ws", options, nullptr);
  EXPECT_EQ(result.num_models, 2);
  ASSERT_EQ(result.cameras.NumViews(), 3);
  EXPECT_EQ(result.cameras.views[0].name, names[2]);
  EXPECT_EQ(result.unregistered, (std::vector<std::string>{names[0], names[1], names[4]}));
  // Photos stayed unregistered, so the mapper ran again with other seeds.
  EXPECT_EQ(result.mapper_runs, options.mapper_attempts);
  const std::string log = ReadFileToString(result.log_path);
  EXPECT_NE(log.find("--random_seed " + std::to_string(options.mapper_attempts - 1)),
            std::string::npos);
  EXPECT_FALSE(fs::exists(scratch.path() / "ws" / "sparse_retry"));
  // Retries relax the mapper's thresholds; 3 of 6 is not too few to match again.
  EXPECT_NE(log.find("--Mapper.init_min_num_inliers 50"), std::string::npos);
  EXPECT_FALSE(result.relaxed_mapping);  // the first run's model was kept
  EXPECT_EQ(result.matching_runs, 1);
}

// Too few photos registered: matching runs again (guided) from the same
// features, and the mapper on its matches; the better model is kept. The
// stand-in's mapper builds the whole model only after guided matching.
TEST(ColmapRunnerTest, TooFewRegisteredPhotosAreMatchedAgain) {
  ScratchDir scratch("match_again");
  const std::vector<std::string> names = DatasetPhotos(0, 6);
  WriteModel(scratch.path() / "weak" / "0", {names[0], names[1]});
  WriteModel(scratch.path() / "strong" / "0", names);
  const fs::path guided = scratch.path() / "guided";
  const fs::path script = scratch.path() / "stand_in_colmap.sh";
  AtomicWriteString(script,
                    "#!/bin/sh\ncommand=$1\nout=\ndb=\nguide=0\n"
                    "while [ $# -gt 0 ]; do\n"
                    "  [ \"$1\" = --output_path ] && out=$2\n"
                    "  [ \"$1\" = --database_path ] && db=$2\n"
                    "  [ \"$1\" = --SiftMatching.guided_matching ] && guide=$2\n"
                    "  shift\ndone\n"
                    "[ \"$command\" = feature_extractor ] && echo features > \"$db\"\n"
                    "[ \"$guide\" = 1 ] && touch '" +
                        guided.string() +
                        "'\n"
                        "if [ \"$command\" = mapper ]; then\n"
                        "  if [ -e '" +
                        guided.string() + "' ]; then cp -r '" +
                        (scratch.path() / "strong").string() +
                        "'/. \"$out\"/\n"
                        "  else cp -r '" +
                        (scratch.path() / "weak").string() +
                        "'/. \"$out\"/; fi\n"
                        "fi\nexit 0\n");
  fs::permissions(script, fs::perms::owner_all);
  ColmapOptions options = FastOptions();
  options.executable = script.string();
  const ColmapResult result =
      RunColmap(kDataset / "images", names, "", scratch.path() / "ws", options, nullptr);
  EXPECT_EQ(result.cameras.NumViews(), 6);
  EXPECT_TRUE(result.unregistered.empty());
  EXPECT_EQ(result.matching_runs, 2);
  EXPECT_EQ(result.mapper_runs, options.mapper_attempts + 1);  // all, then the first after
  EXPECT_TRUE(result.relaxed_mapping);
  ASSERT_EQ(result.notes.size(), 1u);  // for the stage's warnings
  EXPECT_NE(result.notes[0].find("2 of 6 photos at first; matched again"), std::string::npos)
      << result.notes[0];
  EXPECT_FALSE(fs::exists(scratch.path() / "ws" / "database_features.db"));

  // Never matching again keeps the weak model.
  options.rematch_below = 0.0;
  fs::remove(guided);
  const ColmapResult kept =
      RunColmap(kDataset / "images", names, "", scratch.path() / "ws2", options, nullptr);
  EXPECT_EQ(kept.cameras.NumViews(), 2);
  EXPECT_EQ(kept.matching_runs, 1);
}

// A stand-in whose feature extractor hangs (silent, idle) on its first run
// (`hang_always`: on every run); every other command succeeds and the
// mapper copies the models in `models_dir`.
fs::path WriteHangingStandIn(const fs::path& folder, const fs::path& models_dir, bool hang_always) {
  const fs::path script = folder / "hanging_colmap.sh";
  const fs::path marker = folder / "hung_once";
  std::string text = "#!/bin/sh\ncommand=$1\nout=\n";
  text += "while [ $# -gt 0 ]; do [ \"$1\" = --output_path ] && out=$2; shift; done\n";
  text += "if [ \"$command\" = feature_extractor ]; then\n";
  text += hang_always ? "  sleep 60\n"
                      : "  [ -e '" + marker.string() + "' ] || { touch '" + marker.string() +
                            "'; sleep 60; }\n";
  text += "fi\n";
  text += "[ \"$command\" = mapper ] && cp -r '" + models_dir.string() + "'/. \"$out\"/\n";
  text += "echo \"stand-in $command\"\nexit 0\n";
  AtomicWriteString(script, text);
  fs::permissions(script, fs::perms::owner_all);
  return script;
}

// A command that hangs is stopped after stall_seconds and run once more;
// hung twice, it is a registration error naming it, long before it would
// have ended.
TEST(ColmapRunnerTest, HungCommandsAreStoppedAndRunAgain) {
  ScratchDir scratch("hung");
  const std::vector<std::string> names = DatasetPhotos(0, 3);
  WriteModel(scratch.path() / "models" / "0", names);
  ColmapOptions options = FastOptions();
  options.stall_seconds = 2.0;
  options.executable = WriteHangingStandIn(scratch.path(), scratch.path() / "models", false);
  const auto start = std::chrono::steady_clock::now();
  const ColmapResult result =
      RunColmap(kDataset / "images", names, "", scratch.path() / "ws", options, nullptr);
  EXPECT_EQ(result.cameras.NumViews(), 3);
  ASSERT_FALSE(result.notes.empty());
  EXPECT_NE(result.notes[0].find("COLMAP feature_extractor hung"), std::string::npos)
      << result.notes[0];
  EXPECT_NE(ReadFileToString(result.log_path).find("COLMAP has hung and is stopped"),
            std::string::npos);

  options.executable = WriteHangingStandIn(scratch.path(), scratch.path() / "models", true);
  try {
    RunColmap(kDataset / "images", names, "", scratch.path() / "ws2", options, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const RegistrationError& error) {
    EXPECT_NE(std::string(error.what()).find("COLMAP feature_extractor hung"), std::string::npos)
        << error.what();
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 30.0);  // three stalls of ~2-3 s, not the stand-in's 60 s sleeps
}

bool ProcessGone(pid_t pid) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    const fs::path stat_path = "/proc/" + std::to_string(pid) + "/stat";
    if (!fs::exists(stat_path)) return true;
    const std::string stat = ReadFileToString(stat_path);
    const size_t state = stat.rfind(')') + 2;                    // "pid (name) S ..."
    if (state < stat.size() && stat[state] == 'Z') return true;  // killed, awaiting its reaper
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// Cancelling kills the whole process group: a stand-in "colmap" that starts a
// long-running child of its own, reports progress and waits.
TEST(ColmapRunnerTest, CancellingKillsTheProcessGroup) {
  ScratchDir scratch("cancel_group");
  const fs::path pid_file = scratch.path() / "sleeper.pid";
  const fs::path script = scratch.path() / "fake_colmap.sh";
  AtomicWriteString(script, "#!/bin/sh\nsleep 120 &\necho $! > '" + pid_file.string() +
                                "'\necho 'Processed file [1/2]'\nwait\n");
  fs::permissions(script, fs::perms::owner_all);
  ColmapOptions options = FastOptions();
  options.executable = script.string();
  RecordingProgress progress(/*cancel_at_first=*/true);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(RunColmap(kDataset / "images", DatasetPhotos(0, 2), "", scratch.path() / "ws",
                         options, &progress),
               Cancelled);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  const pid_t sleeper = std::stoi(ReadFileToString(pid_file));
  const bool gone = ProcessGone(sleeper);
  EXPECT_TRUE(gone) << "the stand-in's child " << sleeper << " still runs";
  if (!gone) kill(sleeper, SIGKILL);
}

}  // namespace
}  // namespace sylva
