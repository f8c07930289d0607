// End-to-end tests of `sylva batch` with the real binary on small synthetic
// trees (made once by `sylva synth`): a batch with a broken tree and a bad
// per-tree option fails those two alone and reports them; a re-run skips the
// finished trees without touching them; a tree whose process crashes is
// recorded and the others go on; a batch killed with SIGKILL resumes with
// only the unfinished trees; a bad manifest runs nothing.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/io/json_util.h"
#include "core/util/file_util.h"
#include "tests/e2e/subprocess.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

const char kSylva[] = SYLVA_BINARY_DIR "/bin/sylva";
constexpr int kExitBadInput = 2;
constexpr int kExitTreesFailed = 3;
// Small trees: 5 input views and 1 held out of 96 x 96 pixels.
constexpr int kImageSize = 96;
constexpr int kNumDatasets = 3;
// Options that keep a tree's run to a few seconds.
const std::vector<std::string> kFastOptions = {"--Report.preview_size=96"};

using Row = std::map<std::string, std::string>;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

::testing::AssertionResult ExitedWith(const SubprocessResult& result, int code) {
  if (!result.timed_out && result.term_signal == 0 && result.exit_code == code) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "expected exit code " << code << ", got " << result.Describe();
}

// Size, modification time and inode of every file under `root`: what an
// atomic rewrite changes.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    struct stat info {};
    if (entry.is_directory() || lstat(entry.path().c_str(), &info) != 0) continue;
    std::ostringstream facts;
    facts << info.st_size << " " << info.st_mtim.tv_sec << "." << info.st_mtim.tv_nsec << " "
          << info.st_ino;
    files[fs::relative(entry.path(), root).string()] = facts.str();
  }
  return files;
}

// summary.csv as one map per row (column -> value), read with a small CSV
// reader of its own (quotes, doubled quotes), independent of sylva's.
std::vector<Row> ReadSummary(const fs::path& out_dir) {
  const std::string text = ReadFileToString(out_dir / "summary.csv");
  std::vector<std::vector<std::string>> records(1);
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted && c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
      field += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (!quoted && c == ',') {
      records.back().push_back(field);
      field.clear();
    } else if (!quoted && c == '\n') {
      records.back().push_back(field);
      field.clear();
      records.emplace_back();
    } else {
      field += c;
    }
  }
  records.pop_back();  // after the last line end
  std::vector<Row> rows;
  for (size_t r = 1; r < records.size(); ++r) {
    Row row;
    EXPECT_EQ(records[r].size(), records[0].size()) << "row " << r;
    for (size_t c = 0; c < records[0].size() && c < records[r].size(); ++c) {
      row[records[0][c]] = records[r][c];
    }
    rows.push_back(row);
  }
  return rows;
}

Json ReadStatus(const fs::path& out_dir, const std::string& name) {
  return ReadJsonFile(out_dir / "logs" / (name + ".json"));
}

class BatchTest : public ::testing::Test {
 protected:
  // Three synthetic trees (seeds 1-3) in root_/datasets/tree_<k>/.
  static void SetUpTestSuite() {
    std::string templ = (fs::temp_directory_path() / "sylva_batch_e2e_XXXXXX").string();
    if (mkdtemp(templ.data()) == nullptr) {
      setup_error_ = "cannot create a temporary folder";
      return;
    }
    root_ = new fs::path(fs::canonical(templ));
    for (int k = 1; k <= kNumDatasets; ++k) {
      const SubprocessResult synth = RunSubprocess(
          {kSylva, "synth", Dataset(k).string(), "--seed", std::to_string(k), "--size",
           std::to_string(kImageSize), "--samples", "2", "--views", "5", "--held-out", "1"});
      if (synth.exit_code != 0) setup_error_ = "sylva synth failed: " + synth.Describe();
    }
  }

  static void TearDownTestSuite() {
    if (root_ == nullptr) return;
    if (std::getenv("SYLVA_E2E_KEEP") == nullptr) fs::remove_all(*root_);
    delete root_;
    root_ = nullptr;
  }

  void SetUp() override {
    ASSERT_TRUE(setup_error_.empty()) << setup_error_;
    work_ = *root_ / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(work_);
  }

  static fs::path Dataset(int k) { return *root_ / "datasets" / ("tree_" + std::to_string(k)); }

  // A manifest row for dataset folder `dataset` (paths relative to work_).
  std::string ManifestRow(const std::string& name, const fs::path& dataset,
                          const std::string& option = "") const {
    const std::string d = fs::relative(dataset, work_).string();
    return name + "," + d + "/photos," + d + "/cameras.json," + d + "/mattes,@" + d +
           "/held_out.txt," + option + "\n";
  }

  fs::path WriteManifest(const std::vector<std::string>& rows) const {
    std::string text = "name,photos,cameras,mattes,held_out,Density.resolution\n";
    for (const std::string& row : rows) text += row;
    const fs::path path = work_ / "manifest.csv";
    AtomicWriteString(path, text);
    return path;
  }

  // A copy of dataset k in work_ (to break).
  fs::path CopyDataset(int k, const std::string& name) const {
    const fs::path to = work_ / name;
    fs::copy(Dataset(k), to, fs::copy_options::recursive);
    return to;
  }

  static std::vector<std::string> BatchArgs(const fs::path& manifest, const fs::path& out,
                                            const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {kSylva, "batch", manifest.string(), out.string()};
    args.insert(args.end(), kFastOptions.begin(), kFastOptions.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  static fs::path* root_;
  static std::string setup_error_;
  fs::path work_;
};

fs::path* BatchTest::root_ = nullptr;
std::string BatchTest::setup_error_;

// Waits until `predicate` holds (polling), at most `seconds`.
template <typename Predicate>
bool WaitFor(Predicate predicate, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (predicate()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Whether a process runs (a zombie, dead but not yet reaped, does not).
bool IsAlive(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const size_t paren = line.rfind(')');
  return paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] != 'Z';
}

// The tree's status file says `status` (and, if given, one of `stages`).
bool HasStatus(const fs::path& out, const std::string& name, const std::string& status,
               const std::set<std::string>& stages = {}) {
  try {
    const Json json = ReadStatus(out, name);
    return json.at("status") == status &&
           (stages.empty() || stages.count(json.at("stage").get<std::string>()) > 0);
  } catch (const std::exception&) {
    return false;
  }
}

TEST_F(BatchTest, BrokenTreesFailAloneAndReRunsSkipFinishedTrees) {
  const fs::path broken = CopyDataset(3, "broken");
  AtomicWriteString(broken / "photos" / "view_02.png", "this is not an image");
  const fs::path manifest =
      WriteManifest({ManifestRow("tree_1", Dataset(1)), ManifestRow("tree_2", Dataset(2)),
                     ManifestRow("broken", broken), ManifestRow("bad_option", Dataset(1), "abc")});
  const fs::path out = work_ / "out";
  const SubprocessResult first = RunSubprocess(BatchArgs(manifest, out, {"--jobs", "2"}), 900);
  ASSERT_TRUE(ExitedWith(first, kExitTreesFailed));
  std::cout << "[ batch of 4 trees (2 fail), --jobs 2: " << first.seconds << " s ]\n";
  EXPECT_TRUE(Contains(first.err, "4 trees, 0 up to date, 4 to run")) << first.err;
  EXPECT_TRUE(Contains(first.err, "broken: failed in init")) << first.err;
  EXPECT_TRUE(Contains(first.out, "2 ran, 0 up to date, 2 failed")) << first.out;

  std::vector<Row> rows = ReadSummary(out);
  ASSERT_EQ(rows.size(), 4u);
  for (int t = 0; t < 2; ++t) {
    const Row& row = rows[t];
    EXPECT_EQ(row.at("status"), "ok") << row.at("name") << ": " << row.at("error");
    EXPECT_GT(std::stod(row.at("input_mean_iou")), 0.5) << row.at("name");
    EXPECT_GT(std::stod(row.at("held_out_mean_iou")), 0.3) << row.at("name");
    EXPECT_LE(std::stod(row.at("input_min_iou")), std::stod(row.at("input_mean_iou")));
    EXPECT_EQ(row.at("held_out_views"), "1");
    EXPECT_GT(std::stod(row.at("height")), 1.0) << row.at("name");
    EXPECT_GT(std::stoi(row.at("branches")), 0) << row.at("name");
    EXPECT_GT(std::stod(row.at("seconds_density")), 0.0);
    for (const char* file : {"tree_glb", "skeleton_json", "report_html", "preview"}) {
      EXPECT_TRUE(fs::is_regular_file(out / row.at(file))) << row.at("name") << " " << file;
    }
  }
  const Row& failed = rows[2];
  EXPECT_EQ(failed.at("name"), "broken");
  EXPECT_EQ(failed.at("status"), "failed");
  EXPECT_EQ(failed.at("stage"), "init");
  EXPECT_EQ(failed.at("exit_code"), "2");
  EXPECT_TRUE(Contains(failed.at("error"), "view_02.png")) << failed.at("error");
  EXPECT_FALSE(fs::exists(out / "broken")) << "a failed init left a project behind";
  EXPECT_TRUE(Contains(ReadFileToString(out / failed.at("log")), "sylva: error:"));
  const Row& bad_option = rows[3];
  EXPECT_EQ(bad_option.at("status"), "failed");
  EXPECT_EQ(bad_option.at("stage"), "options");
  EXPECT_TRUE(Contains(bad_option.at("error"), "manifest.csv:5")) << bad_option.at("error");
  EXPECT_TRUE(Contains(bad_option.at("error"), "Density.resolution")) << bad_option.at("error");

  const std::string html = ReadFileToString(out / "summary.html");
  EXPECT_TRUE(Contains(html, "src='tree_1/out/report/preview_0.png'")) << html;
  EXPECT_TRUE(Contains(html, "<svg")) << html;

  // Again: the finished trees are skipped and left exactly as they were.
  const auto tree_1 = Snapshot(out / "tree_1"), tree_2 = Snapshot(out / "tree_2");
  const SubprocessResult again = RunSubprocess(BatchArgs(manifest, out, {"--jobs", "2"}), 900);
  ASSERT_TRUE(ExitedWith(again, kExitTreesFailed));
  EXPECT_TRUE(Contains(again.err, "4 trees, 2 up to date, 2 to run")) << again.err;
  EXPECT_TRUE(Snapshot(out / "tree_1") == tree_1) << "an up-to-date tree was touched";
  EXPECT_TRUE(Snapshot(out / "tree_2") == tree_2) << "an up-to-date tree was touched";

  // Repaired: only the two that failed run, and the batch succeeds.
  fs::copy_file(Dataset(3) / "photos" / "view_02.png", broken / "photos" / "view_02.png",
                fs::copy_options::overwrite_existing);
  WriteManifest({ManifestRow("tree_1", Dataset(1)), ManifestRow("tree_2", Dataset(2)),
                 ManifestRow("broken", broken), ManifestRow("bad_option", Dataset(1), "48")});
  const SubprocessResult fixed = RunSubprocess(BatchArgs(manifest, out, {"--jobs", "2"}), 900);
  ASSERT_TRUE(ExitedWith(fixed, 0));
  EXPECT_TRUE(Contains(fixed.err, "4 trees, 2 up to date, 2 to run")) << fixed.err;
  rows = ReadSummary(out);
  // The skipped trees keep the record of the run that made them.
  for (const Row& row : rows) EXPECT_EQ(row.at("status"), "ok") << row.at("name");
  EXPECT_TRUE(Snapshot(out / "tree_1") == tree_1) << "an up-to-date tree was touched";
  const Json run = ReadJsonFile(out / "bad_option" / "out" / "run.json");
  EXPECT_EQ(run.at("options").at("Density").at("resolution").get<int>(), 48);
}

TEST_F(BatchTest, ACrashedTreeIsRecordedAndTheOthersGoOn) {
  const fs::path manifest =
      WriteManifest({ManifestRow("tree_1", Dataset(1)), ManifestRow("tree_2", Dataset(2))});
  const fs::path out = work_ / "out";
  Subprocess batch(BatchArgs(manifest, out));
  // Crash tree_1's process once it is inside a stage.
  ASSERT_TRUE(WaitFor(
      [&] {
        return HasStatus(out, "tree_1", "running", {"density", "attract"});
      },
      300));
  const int pid = ReadStatus(out, "tree_1").at("pid").get<int>();
  ASSERT_EQ(kill(pid, SIGSEGV), 0);
  const SubprocessResult result = batch.Wait(600);
  ASSERT_TRUE(ExitedWith(result, kExitTreesFailed));
  const std::vector<Row> rows = ReadSummary(out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("status"), "crashed");
  const std::set<std::string> stages = {"density", "attract", "skeleton", "mesh", "report"};
  EXPECT_EQ(stages.count(rows[0].at("stage")), 1u) << rows[0].at("stage");
  EXPECT_TRUE(Contains(rows[0].at("error"), "signal 11")) << rows[0].at("error");
  EXPECT_EQ(rows[1].at("status"), "ok") << rows[1].at("error");
}

TEST_F(BatchTest, AKilledBatchResumesWithOnlyTheUnfinishedTrees) {
  const fs::path manifest =
      WriteManifest({ManifestRow("tree_1", Dataset(1)), ManifestRow("tree_2", Dataset(2)),
                     ManifestRow("tree_3", Dataset(3))});
  const fs::path out = work_ / "out";
  int pid = 0;
  {
    Subprocess batch(BatchArgs(manifest, out));
    // Kill the batch (SIGKILL: no clean-up) while tree_2 is past its density.
    ASSERT_TRUE(WaitFor(
        [&] {
          return HasStatus(out, "tree_2", "running", {"attract", "skeleton"});
        },
        300));
    pid = ReadStatus(out, "tree_2").at("pid").get<int>();
    batch.Signal(SIGKILL);
    batch.Wait(30);
  }
  // The tree's process dies with the batch.
  EXPECT_TRUE(WaitFor([&] { return !IsAlive(pid); }, 10)) << "tree_2's process outlived the batch";
  EXPECT_TRUE(HasStatus(out, "tree_1", "ok"));
  const auto tree_1 = Snapshot(out / "tree_1");
  const SubprocessResult resumed = RunSubprocess(BatchArgs(manifest, out), 900);
  ASSERT_TRUE(ExitedWith(resumed, 0));
  EXPECT_TRUE(Contains(resumed.err, "3 trees, 1 up to date, 2 to run")) << resumed.err;
  EXPECT_TRUE(Snapshot(out / "tree_1") == tree_1);
  // tree_2 picks up after its finished stages.
  const Json tree_2 = ReadStatus(out, "tree_2");
  EXPECT_EQ(tree_2.at("status"), "ok");
  const auto stages_run = tree_2.at("stages_run").get<std::vector<std::string>>();
  EXPECT_FALSE(stages_run.empty());
  for (const char* done : {"register", "density"}) {
    EXPECT_EQ(std::count(stages_run.begin(), stages_run.end(), done), 0)
        << done << " ran again: " << tree_2.dump();
  }
  for (const Row& row : ReadSummary(out)) {
    EXPECT_TRUE(row.at("status") == "ok" || row.at("status") == "up-to-date") << row.at("name");
  }
}

TEST_F(BatchTest, BadManifestsAndOptionsRunNothing) {
  const fs::path out = work_ / "out";
  const std::string header = "name,photos,cameras,mattes,held_out,Density.resolution\n";
  const struct {
    std::string text;
    std::string expected;  // in the one error line
  } cases[] = {
      {"name,photos,cameras,species\n" + ManifestRow("t", Dataset(1)),
       "manifest.csv:1: unknown column 'species'"},
      {header + ManifestRow("t", Dataset(1)) + ManifestRow("t", Dataset(2)),
       "manifest.csv:3: duplicate name 't'"},
      {header + ManifestRow("", Dataset(1)), "manifest.csv:2: the tree has no name"},
      {header + ManifestRow("t", work_ / "nowhere"), "manifest.csv:2: 'photos': folder not found"},
  };
  for (const auto& c : cases) {
    AtomicWriteString(work_ / "manifest.csv", c.text);
    const SubprocessResult result = RunSubprocess(BatchArgs(work_ / "manifest.csv", out));
    EXPECT_TRUE(ExitedWith(result, kExitBadInput)) << c.text;
    EXPECT_TRUE(Contains(result.err, "sylva: error: ")) << result.err;
    EXPECT_TRUE(Contains(result.err, c.expected)) << result.err;
    EXPECT_FALSE(fs::exists(out)) << "a refused batch created " << out;
  }
  const fs::path manifest = WriteManifest({ManifestRow("t", Dataset(1))});
  const SubprocessResult bad_engine = RunSubprocess(BatchArgs(manifest, out, {"--engine", "make"}));
  EXPECT_TRUE(ExitedWith(bad_engine, kExitBadInput));
  EXPECT_TRUE(Contains(bad_engine.err, "--engine")) << bad_engine.err;
  EXPECT_TRUE(ExitedWith(RunSubprocess({kSylva, "batch"}), kExitBadInput));
  const SubprocessResult help = RunSubprocess({kSylva, "batch", "--help"});
  ASSERT_TRUE(ExitedWith(help, 0));
  for (const char* flag : {"--jobs N", "--scan DIR", "--only NAME", "--engine", "--profile",
                           "--Density.resolution="}) {
    EXPECT_TRUE(Contains(help.out, flag)) << flag << "\n" << help.out;
  }
  const SubprocessResult bad_option =
      RunSubprocess(BatchArgs(manifest, out, {"--Density.resolution=abc"}));
  EXPECT_TRUE(ExitedWith(bad_option, kExitBadInput));
  EXPECT_TRUE(Contains(bad_option.err, "--Density.resolution")) << bad_option.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(BatchTest, ScanWritesAManifestOfTreeFolders) {
  const fs::path manifest = work_ / "scanned.csv";
  const SubprocessResult scan = RunSubprocess(
      {kSylva, "batch", "--scan", (*root_ / "datasets").string(), "--output", manifest.string()});
  ASSERT_TRUE(ExitedWith(scan, 0));
  const std::string text = ReadFileToString(manifest);
  EXPECT_TRUE(
      Contains(text, "name,photos,colmap,cameras,register,loose_cameras,mattes,held_out,units\n"))
      << text;
  EXPECT_TRUE(Contains(text,
                       "tree_2,../datasets/tree_2/photos,,../datasets/tree_2/cameras.json,,,"
                       "../datasets/tree_2/mattes,heldout_00.png,\n"))
      << text;
  // Refuses to overwrite, and the manifest it wrote reads back.
  const SubprocessResult again = RunSubprocess(
      {kSylva, "batch", "--scan", (*root_ / "datasets").string(), "--output", manifest.string()});
  EXPECT_TRUE(ExitedWith(again, kExitBadInput));
  const SubprocessResult summary =
      RunSubprocess({kSylva, "batch", manifest.string(), (work_ / "out").string(), "--summary"});
  ASSERT_TRUE(ExitedWith(summary, 0));
  const std::vector<Row> rows = ReadSummary(work_ / "out");
  ASSERT_EQ(rows.size(), 3u);
  for (const Row& row : rows) EXPECT_EQ(row.at("status"), "not-run");
}

// The same trees through Snakemake (workflow/Snakefile, local profile) give
// the same outputs as the built-in runner, and a broken tree fails alone.
TEST_F(BatchTest, SnakemakeRunsTheSameBatch) {
  const fs::path broken = CopyDataset(3, "broken");
  AtomicWriteString(broken / "photos" / "view_02.png", "this is not an image");
  const fs::path manifest =
      WriteManifest({ManifestRow("tree_1", Dataset(1)), ManifestRow("tree_2", Dataset(2)),
                     ManifestRow("broken", broken)});
  const SubprocessResult engine = RunSubprocess(
      BatchArgs(manifest, work_ / "snakemake", {"--engine", "snakemake", "--profile", "local"}),
      900);
  ASSERT_TRUE(ExitedWith(engine, kExitTreesFailed));
  std::cout << "[ snakemake batch of 3 trees (1 fails): " << engine.seconds << " s ]\n";
  const SubprocessResult native = RunSubprocess(BatchArgs(manifest, work_ / "native"), 900);
  ASSERT_TRUE(ExitedWith(native, kExitTreesFailed));
  std::cout << "[ sylva batch of the same: " << native.seconds << " s ]\n";
  const std::vector<Row> by_engine = ReadSummary(work_ / "snakemake");
  const std::vector<Row> by_sylva = ReadSummary(work_ / "native");
  ASSERT_EQ(by_engine.size(), 3u);
  ASSERT_EQ(by_sylva.size(), 3u);
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(by_engine[t].at("status"), "ok") << by_engine[t].at("error");
    for (const char* figure :
         {"input_mean_iou", "held_out_mean_iou", "mesh_input_mean_iou", "height", "crown_width"}) {
      EXPECT_NEAR(std::stod(by_engine[t].at(figure)), std::stod(by_sylva[t].at(figure)),
                  0.02 * std::abs(std::stod(by_sylva[t].at(figure))))
          << by_engine[t].at("name") << " " << figure;
    }
    EXPECT_TRUE(fs::is_regular_file(work_ / "snakemake" / by_engine[t].at("tree_glb")));
  }
  EXPECT_EQ(by_engine[2].at("status"), "failed");
  EXPECT_EQ(by_engine[2].at("stage"), "init");
  EXPECT_EQ(by_engine[2].at("error"), by_sylva[2].at("error"));
  EXPECT_TRUE(
      Contains(ReadFileToString(work_ / "snakemake" / "logs" / "broken.log"), "sylva: error:"));
}

// A Snakemake job whose tree process crashes is recorded as crashed.
TEST_F(BatchTest, SnakemakeRecordsACrashedJob) {
  const fs::path manifest = WriteManifest({ManifestRow("tree_1", Dataset(1))});
  const fs::path out = work_ / "out";
  Subprocess batch(BatchArgs(manifest, out, {"--engine", "snakemake"}));
  ASSERT_TRUE(WaitFor(
      [&] {
        return HasStatus(out, "tree_1", "running", {"density", "attract"});
      },
      300));
  ASSERT_EQ(kill(ReadStatus(out, "tree_1").at("pid").get<int>(), SIGSEGV), 0);
  ASSERT_TRUE(ExitedWith(batch.Wait(300), kExitTreesFailed));
  const std::vector<Row> rows = ReadSummary(out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "crashed");
  EXPECT_TRUE(rows[0].at("stage") == "density" || rows[0].at("stage") == "attract" ||
              rows[0].at("stage") == "skeleton")
      << rows[0].at("stage");
}

}  // namespace
}  // namespace sylva
