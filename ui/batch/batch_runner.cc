#include "ui/batch/batch_runner.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <deque>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "core/util/check.h"
#include "ui/batch/batch_summary.h"
#include "ui/batch/child_process.h"
#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

// How often running trees are polled.
constexpr auto kPollInterval = std::chrono::milliseconds(100);
constexpr int kExitCancelled = 130;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string Duration(double seconds) {
  const long total = std::lround(std::max(seconds, 0.0));
  std::ostringstream text;
  if (total >= 3600) text << total / 3600 << "h";
  if (total >= 60) text << (total % 3600) / 60 << "m";
  text << total % 60 << "s";
  return text.str();
}

std::string NowText() {
  const std::time_t now = std::time(nullptr);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  return buffer;
}

// Holds an exclusive lock on OUT_DIR/logs/batch.lock while the batch runs:
// two batches writing the same projects would spoil each other's runs.
class OutDirLock {
 public:
  explicit OutDirLock(const fs::path& out_dir) {
    const fs::path path = BatchLogDir(out_dir) / "batch.lock";
    fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    SYLVA_CHECK_INPUT(fd_ >= 0, path.string()) << "cannot create: " << std::strerror(errno);
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      close(fd_);
      SYLVA_INPUT_ERROR(out_dir.string()) << "another 'sylva batch' is running on this folder";
    }
  }
  ~OutDirLock() { close(fd_); }  // releases the lock
  OutDirLock(const OutDirLock&) = delete;
  OutDirLock& operator=(const OutDirLock&) = delete;

 private:
  int fd_ = -1;
};

class BatchScheduler {
 public:
  BatchScheduler(const Manifest& manifest, const fs::path& out_dir, const BatchOptions& options,
                 const std::atomic<bool>* interrupt)
      : manifest_(manifest),
        out_dir_(out_dir),
        options_(options),
        interrupt_(interrupt),
        is_terminal_(isatty(fileno(stderr)) != 0) {}

  BatchResult Run() {
    const Clock::time_point start = Clock::now();
    result_.num_trees = static_cast<int>(manifest_.trees.size());
    Plan();
    while (!queue_.empty() || !running_.empty()) {
      if (Interrupted()) queue_.clear();
      while (!queue_.empty() && static_cast<int>(running_.size()) < options_.jobs) {
        Start(*queue_.front());
        queue_.pop_front();
      }
      ShowProgress();
      std::this_thread::sleep_for(kPollInterval);
      Reap();
    }
    result_.num_interrupted =
        result_.num_trees - result_.num_ok - result_.num_up_to_date - result_.num_failed;
    result_.seconds = SecondsSince(start);
    EndProgressLine();
    return result_;
  }

 private:
  struct Running {
    const ManifestTree* tree;
    std::unique_ptr<ChildProcess> child;
    Clock::time_point start;
  };

  // Queues every tree but those that are finished and up to date.
  void Plan() {
    for (const ManifestTree& tree : manifest_.trees) {
      if (TreeIsUpToDate(manifest_, tree, out_dir_, options_.options)) {
        ++result_.num_up_to_date;
      } else {
        queue_.push_back(&tree);
      }
    }
    Event("batch: " + std::to_string(manifest_.trees.size()) + " trees, " +
          std::to_string(result_.num_up_to_date) + " up to date, " + std::to_string(queue_.size()) +
          " to run, " + std::to_string(options_.jobs) + " at a time");
  }

  bool Interrupted() {
    if (interrupt_ == nullptr || !interrupt_->load() || interrupted_) return interrupted_;
    interrupted_ = true;
    Event("batch: interrupted; stopping the running trees (their finished stages are kept)");
    for (Running& running : running_) running.child->Interrupt();
    return true;
  }

  std::vector<std::string> ChildArguments(const ManifestTree& tree) const {
    const fs::path program = options_.program.empty() ? SelfExecutablePath() : options_.program;
    std::vector<std::string> argv = {program.string(),  "batch",  manifest_.path.string(),
                                     out_dir_.string(), "--only", tree.name};
    if (!options_.log_level.empty()) {
      argv.insert(argv.end(), {"--log-level", options_.log_level});
    }
    bool threads_given = false;
    for (const auto& [key, value] : options_.options) {
      argv.push_back("--" + key + "=" + value);
      threads_given = threads_given || key == "General.num_threads";
    }
    // Trees running side by side share the cores rather than each taking all.
    if (options_.jobs > 1 && !threads_given) {
      const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      argv.push_back("--General.num_threads=" + std::to_string(std::max(1, cores / options_.jobs)));
    }
    return argv;
  }

  void Start(const ManifestTree& tree) {
    const std::vector<std::string> argv = ChildArguments(tree);
    const fs::path log = TreeLogPath(out_dir_, tree.name);
    {
      std::ofstream header(log, std::ios::app);
      header << "\n== sylva batch, " << NowText() << ":";
      for (const std::string& arg : argv) header << " " << arg;
      header << "\n";
    }
    running_.push_back({&tree, std::make_unique<ChildProcess>(argv, log), Clock::now()});
  }

  void Reap() {
    for (auto it = running_.begin(); it != running_.end();) {
      if (!it->child->Poll()) {
        ++it;
        continue;
      }
      if (Record(*it)) ok_seconds_.push_back(SecondsSince(it->start));
      all_seconds_.push_back(SecondsSince(it->start));
      it = running_.erase(it);
      WriteBatchSummary(manifest_, out_dir_);
    }
  }

  // The tree's status as its run left it, completed where the run could not
  // write it (killed, crashed).
  TreeStatus FinalStatus(const Running& running) const {
    const ChildProcess& child = *running.child;
    const fs::path path = TreeStatusPath(out_dir_, running.tree->name);
    TreeStatus status = ReadTreeStatus(path).value_or(TreeStatus());
    status.name = running.tree->name;
    if (child.term_signal() != 0) {
      status.status = "crashed";
      status.error = std::string("killed by signal ") + std::to_string(child.term_signal()) + " (" +
                     strsignal(child.term_signal()) + ")";
      status.exit_code = -1;
    } else if (status.status == "running" || status.status == "not-run" ||
               status.exit_code != child.exit_code()) {
      status.status = "failed";
      status.error = "exited with code " + std::to_string(child.exit_code()) +
                     " without recording how it ended (see its log)";
      status.exit_code = child.exit_code();
    } else {
      return status;
    }
    status.seconds = SecondsSince(running.start);
    WriteTreeStatus(path, status);
    return status;
  }

  // Reports how the tree's run ended; true if it finished.
  bool Record(const Running& running) {
    const TreeStatus status = FinalStatus(running);
    const std::string& name = running.tree->name;
    if (status.Finished()) {
      ++(status.status == "ok" ? result_.num_ok : result_.num_up_to_date);
      Event(name + ": " + status.status + " (" + Duration(status.seconds) + ")");
    } else if (status.status == "interrupted" || status.exit_code == kExitCancelled) {
      Event(name + ": interrupted in " + status.stage);
    } else {
      ++result_.num_failed;
      Event(name + ": " + status.status + " in " + status.stage + ": " + status.error +
            " (log: " + TreeLogPath(out_dir_, name).string() + ")");
    }
    return status.Finished();
  }

  // Remaining wall time from the mean time of the trees that finished so far
  // (failures are quick: they would make it too short), else of all.
  std::string Eta() const {
    const std::vector<double>& times = ok_seconds_.empty() ? all_seconds_ : ok_seconds_;
    if (times.empty()) return "ETA unknown";
    double mean = 0.0;
    for (double s : times) mean += s / times.size();
    double work = mean * queue_.size();
    for (const Running& running : running_)
      work += std::max(mean - SecondsSince(running.start), 0.0);
    const int lanes = std::max(1, std::min<int>(options_.jobs, queue_.size() + running_.size()));
    return "ETA " + Duration(work / lanes);
  }

  std::string ProgressText() const {
    const int done = result_.num_ok + result_.num_up_to_date + result_.num_failed;
    std::ostringstream text;
    text << "batch: " << done << "/" << result_.num_trees << " done (" << result_.num_ok << " ok, "
         << result_.num_up_to_date << " up to date, " << result_.num_failed << " failed), "
         << running_.size() << " running";
    if (!queue_.empty() || !running_.empty()) text << ", " << Eta();
    return text.str();
  }

  // On a terminal a rewritten line; in a log a line when the counts change.
  void ShowProgress() {
    const std::string text = ProgressText();
    if (is_terminal_) {
      std::fprintf(stderr, "\r\033[K%s", text.c_str());
      std::fflush(stderr);
      line_open_ = true;
    } else if (text.substr(0, text.find(", ETA")) != last_progress_) {
      last_progress_ = text.substr(0, text.find(", ETA"));
      std::fprintf(stderr, "%s\n", text.c_str());
    }
  }

  // A line that stays (a tree finished or failed).
  void Event(const std::string& text) {
    EndProgressLine();
    std::fprintf(stderr, "%s\n", text.c_str());
  }

  void EndProgressLine() {
    if (line_open_) std::fprintf(stderr, "\r\033[K");
    line_open_ = false;
  }

  const Manifest& manifest_;
  const fs::path out_dir_;
  const BatchOptions& options_;
  const std::atomic<bool>* interrupt_;
  const bool is_terminal_;
  bool interrupted_ = false;
  bool line_open_ = false;
  std::string last_progress_;
  std::deque<const ManifestTree*> queue_;
  std::vector<Running> running_;
  std::vector<double> ok_seconds_;   // wall times of the trees that finished
  std::vector<double> all_seconds_;  // of every tree run
  BatchResult result_;
};

}  // namespace

int BatchResult::ExitCode() const {
  if (num_interrupted > 0) return kExitCancelled;
  return num_failed > 0 ? kBatchExitTreesFailed : 0;
}

std::string BatchResult::BriefReport() const {
  std::ostringstream text;
  text << "Batch of " << num_trees << " trees in " << Duration(seconds) << ": " << num_ok
       << " ran, " << num_up_to_date << " up to date, " << num_failed << " failed";
  if (num_interrupted > 0) text << ", " << num_interrupted << " interrupted or not run";
  return text.str();
}

void CheckBatchOptions(const OptionList& options) {
  PipelineOptions values;
  OptionRegistry registry;
  RegisterPipelineOptions(&values, &registry);
  for (const auto& [key, value] : options) registry.Set(key, value, "--" + key);
  values.Check();
}

BatchResult RunBatch(const Manifest& manifest, const fs::path& out_dir, const BatchOptions& options,
                     const std::atomic<bool>* interrupt) {
  SYLVA_CHECK(options.jobs >= 1) << "jobs must be >= 1";
  const fs::path out = fs::absolute(out_dir).lexically_normal();
  std::error_code ec;
  fs::create_directories(BatchLogDir(out), ec);
  SYLVA_CHECK_INPUT(!ec, out.string()) << "cannot create the output folder: " << ec.message();
  const OutDirLock lock(out);
  const BatchResult result = BatchScheduler(manifest, out, options, interrupt).Run();
  WriteBatchSummary(manifest, out);
  return result;
}

}  // namespace sylva
