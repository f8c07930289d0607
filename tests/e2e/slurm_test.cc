// End-to-end test of `sylva batch --engine snakemake --profile slurm` on a
// real Slurm: a one-node cluster on localhost (munged, slurmctld, slurmd from
// Debian's munge and slurm-wlm) started for the test by
// scripts/local-slurm.sh in BUILD/local-slurm-test/ and stopped after it,
// pass or fail (and by CTest's clean-up test sylva_slurm_e2e_stop if this
// process is killed). Two small synthetic trees go through Slurm as one job each; the test
// checks that both finish with the same figures as the built-in runner, and
// that Slurm ran them: the job ids Snakemake reports are in Slurm's job
// completion log, completed, with the tree rule's 2 CPUs. It fails (never
// skips) when Slurm cannot run here.
#include <gtest/gtest.h>
#include <pwd.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "core/util/file_util.h"
#include "tests/e2e/subprocess.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

const char kSylva[] = SYLVA_BINARY_DIR "/bin/sylva";
const char kLocalSlurm[] = SYLVA_SOURCE_DIR "/scripts/local-slurm.sh";
const char kSlurmProfile[] = SYLVA_SOURCE_DIR "/workflow/profiles/slurm/config.yaml";
// The cluster's configuration, state and logs (the same folder as CTest's
// clean-up test stops).
const char kSlurmDir[] = SYLVA_BINARY_DIR "/local-slurm-test";
constexpr int kNumTrees = 2;
// Options that keep a tree's run to a few seconds.
const std::vector<std::string> kFastOptions = {"--Report.preview_size=96"};

using Row = std::map<std::string, std::string>;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// summary.csv as one map per row (column -> value); the summary's fields
// used here hold no commas or quotes.
std::vector<Row> ReadSummary(const fs::path& out_dir) {
  std::istringstream text(ReadFileToString(out_dir / "summary.csv"));
  std::vector<std::vector<std::string>> records;
  for (std::string line; std::getline(text, line);) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string field; std::getline(cells, field, ',');) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    records.push_back(fields);
  }
  std::vector<Row> rows;
  for (size_t r = 1; r < records.size(); ++r) {
    Row row;
    for (size_t c = 0; c < records[0].size() && c < records[r].size(); ++c) {
      row[records[0][c]] = records[r][c];
    }
    rows.push_back(row);
  }
  return rows;
}

class SlurmBatchTest : public ::testing::Test {
 protected:
  // Starts the cluster and makes the trees (seeds 1-2) in root_/datasets/.
  static void SetUpTestSuite() {
    std::string templ = (fs::temp_directory_path() / "sylva_slurm_e2e_XXXXXX").string();
    if (mkdtemp(templ.data()) == nullptr) {
      setup_error_ = "cannot create a temporary folder";
      return;
    }
    root_ = new fs::path(fs::canonical(templ));
    // Stop first: a cluster left by a killed run would be taken as it is.
    RunSubprocess({kLocalSlurm, "stop", SlurmDir().string()}, 120);
    const SubprocessResult start = RunSubprocess({kLocalSlurm, "start", SlurmDir().string()}, 180);
    std::cout << "[ local Slurm started in " << start.seconds << " s ]\n";
    started_ = true;  // whatever it says: stop cleans up what did start
    if (start.exit_code != 0) {
      setup_error_ = "Slurm cannot run here: " + start.Describe();
      return;
    }
    // Snakemake's Slurm executor and sylva's jobs use this cluster alone.
    setenv("SLURM_CONF", (SlurmDir() / "etc" / "slurm.conf").c_str(), 1);
    // Snakemake's Slurm executor reads $USER (to guess an account).
    if (std::getenv("USER") == nullptr) {
      const passwd* user = getpwuid(getuid());
      setenv("USER", user != nullptr ? user->pw_name : "root", 1);
    }
    for (int k = 1; k <= kNumTrees; ++k) {
      const SubprocessResult synth =
          RunSubprocess({kSylva, "synth", Dataset(k).string(), "--seed", std::to_string(k),
                         "--size", "96", "--samples", "2", "--views", "5", "--held-out", "1"});
      if (synth.exit_code != 0) setup_error_ = "sylva synth failed: " + synth.Describe();
    }
  }

  static void TearDownTestSuite() {
    if (root_ == nullptr) return;
    if (started_) {
      const SubprocessResult stop = RunSubprocess({kLocalSlurm, "stop", SlurmDir().string()}, 120);
      EXPECT_EQ(stop.exit_code, 0) << stop.Describe();
    }
    if (std::getenv("SYLVA_E2E_KEEP") == nullptr) fs::remove_all(*root_);
    delete root_;
    root_ = nullptr;
  }

  void SetUp() override { ASSERT_TRUE(setup_error_.empty()) << setup_error_; }

  static fs::path SlurmDir() { return kSlurmDir; }
  static fs::path Dataset(int k) { return *root_ / "datasets" / ("tree_" + std::to_string(k)); }

  static fs::path WriteManifest() {
    std::string text = "name,photos,cameras,mattes,held_out\n";
    for (int k = 1; k <= kNumTrees; ++k) {
      const std::string d = "datasets/tree_" + std::to_string(k);
      text += "tree_" + std::to_string(k) + "," + d + "/photos," + d + "/cameras.json," + d +
              "/mattes,@" + d + "/held_out.txt\n";
    }
    const fs::path path = *root_ / "manifest.csv";
    AtomicWriteString(path, text);
    return path;
  }

  static fs::path* root_;
  static bool started_;
  static std::string setup_error_;
};

fs::path* SlurmBatchTest::root_ = nullptr;
bool SlurmBatchTest::started_ = false;
std::string SlurmBatchTest::setup_error_;

TEST_F(SlurmBatchTest, TwoTreesGoThroughSlurm) {
  const fs::path manifest = WriteManifest();
  // The slurm profile as it is, polling Slurm every second instead of every
  // 30 s (Snakemake's default for Slurm), so that the test does not wait.
  const fs::path profile = *root_ / "slurm-profile";
  fs::create_directories(profile);
  AtomicWriteString(profile / "config.yaml",
                    ReadFileToString(kSlurmProfile) + "max-status-checks-per-second: 1\n");
  const fs::path out = *root_ / "slurm-out";
  std::vector<std::string> args = {kSylva,     "batch",     manifest.string(), out.string(),
                                   "--engine", "snakemake", "--profile",       profile.string()};
  args.insert(args.end(), kFastOptions.begin(), kFastOptions.end());
  const SubprocessResult batch = RunSubprocess(args, 600);
  ASSERT_EQ(batch.exit_code, 0) << batch.Describe();
  std::cout << "[ batch of " << kNumTrees << " trees through Slurm: " << batch.seconds << " s ]\n";

  const std::vector<Row> rows = ReadSummary(out);
  ASSERT_EQ(rows.size(), static_cast<size_t>(kNumTrees));
  for (const Row& row : rows) {
    EXPECT_EQ(row.at("status"), "ok") << row.at("name") << ": " << row.at("error");
    EXPECT_TRUE(fs::is_regular_file(out / row.at("tree_glb"))) << row.at("name");
  }

  // Snakemake submitted one Slurm job per tree ...
  const std::string log = batch.out + batch.err;
  const std::regex submitted("has been submitted with SLURM jobid ([0-9]+)");
  std::vector<std::string> job_ids;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), submitted);
       it != std::sregex_iterator(); ++it) {
    job_ids.push_back((*it)[1]);
  }
  ASSERT_EQ(job_ids.size(), static_cast<size_t>(kNumTrees)) << log;
  // ... which Slurm ran to completion with the tree rule's 2 CPUs, each one
  // tree (its Slurm log, written by the job, shows which).
  const std::string completed = ReadFileToString(SlurmDir() / "log" / "jobcomp.txt");
  std::map<std::string, int> trees_run;
  for (const std::string& id : job_ids) {
    const std::regex record("JobId=" + id + " [^\n]*");
    std::smatch match;
    ASSERT_TRUE(std::regex_search(completed, match, record)) << "job " << id << "\n" << completed;
    const std::string line = match.str();
    EXPECT_TRUE(Contains(line, "Name=snakejob_tree_")) << line;
    EXPECT_TRUE(Contains(line, "JobState=COMPLETED")) << line;
    EXPECT_TRUE(Contains(line, "ProcCnt=2")) << line;
    const fs::path job_log = out / ".snakemake" / "slurm_logs" / "rule_tree" / (id + ".log");
    ASSERT_TRUE(fs::is_regular_file(job_log)) << job_log;
    const std::string job_text = ReadFileToString(job_log);
    EXPECT_TRUE(Contains(job_text, "--General.num_threads=2")) << job_text;
    for (int k = 1; k <= kNumTrees; ++k) {
      trees_run["tree_" + std::to_string(k)] +=
          Contains(job_text, "--only tree_" + std::to_string(k) + " ");
    }
  }
  for (int k = 1; k <= kNumTrees; ++k) EXPECT_EQ(trees_run["tree_" + std::to_string(k)], 1);

  // The same trees by the built-in runner give the same figures.
  std::vector<std::string> native_args = {kSylva, "batch", manifest.string(),
                                          (*root_ / "native-out").string()};
  native_args.insert(native_args.end(), kFastOptions.begin(), kFastOptions.end());
  const SubprocessResult native = RunSubprocess(native_args, 600);
  ASSERT_EQ(native.exit_code, 0) << native.Describe();
  std::cout << "[ the same trees by sylva batch: " << native.seconds << " s ]\n";
  const std::vector<Row> by_sylva = ReadSummary(*root_ / "native-out");
  ASSERT_EQ(by_sylva.size(), rows.size());
  for (size_t t = 0; t < rows.size(); ++t) {
    for (const char* figure : {"input_mean_iou", "held_out_mean_iou", "height", "crown_width"}) {
      EXPECT_NEAR(std::stod(rows[t].at(figure)), std::stod(by_sylva[t].at(figure)),
                  0.02 * std::abs(std::stod(by_sylva[t].at(figure))))
          << rows[t].at("name") << " " << figure;
    }
  }
}

}  // namespace
}  // namespace sylva
