#include "reconstruct/registration/colmap_runner.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/io/colmap_model.h"
#include "core/io/image_io.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"

extern char** environ;

namespace sylva {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr char kDatabaseName[] = "database.db";
constexpr char kSparseFolder[] = "sparse";
constexpr char kRetryFolder[] = "sparse_retry";
constexpr char kImageListName[] = "image_list.txt";
constexpr char kLogName[] = "colmap.log";

// COLMAP's mapper drops models with fewer images than
// min(Mapper.min_model_size, 0.8 x photos); its default (10) would drop the
// only model of a small photo set, so every model of 2 or more photos is
// kept here and the largest is chosen afterwards.
constexpr int kMinModelSize = 2;
// The mapper's thresholds on retries, half COLMAP's defaults (100 inliers and
// 16 degrees for the initial pair, 30 inliers for each next photo): a plant
// on a turntable gives few verified matches per pair, and a run whose
// matches came out a little weaker (COLMAP's matching is not reproducible on
// the CPU) otherwise finds no initial pair good enough and registers 2 of 8.
const std::pair<const char*, const char*> kRelaxedMapper[] = {
    {"--Mapper.init_min_num_inliers", "50"},
    {"--Mapper.init_min_tri_angle", "8"},
    {"--Mapper.abs_pose_min_num_inliers", "15"}};
// The features-only database kept for a second matching pass.
constexpr char kFeaturesDatabaseName[] = "database_features.db";
// The fewest registered photos that make a usable model.
constexpr int kMinRegisteredPhotos = 2;
// Lines of COLMAP's output quoted in error messages.
constexpr size_t kQuotedLogLines = 12;
// How often a running command is checked for cancellation (milliseconds).
constexpr int kPollIntervalMs = 100;
// How often a running command's CPU time is read (seconds).
constexpr double kCpuCheckSeconds = 1.0;
// The share of the whole run given to extraction and matching in progress
// reports (mapping takes the rest).
constexpr double kExtractionEnd = 0.25;
constexpr double kMatchingEnd = 0.7;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---------------------------------------------------------------------------
// Progress parsed from COLMAP's output lines. Each parser returns the
// command's completed fraction, or a negative value if the line carries none.

using ProgressParser = std::function<double(const std::string& line)>;

// "Processed file [3/24]".
double ExtractionProgress(const std::string& line) {
  int done = 0, total = 0;
  if (std::sscanf(line.c_str(), "Processed file [%d/%d]", &done, &total) != 2) return -1;
  return total > 0 ? static_cast<double>(done) / total : -1;
}

// "Matching block [2/3, 1/3] in 1.2s".
double ExhaustiveProgress(const std::string& line) {
  int row = 0, rows = 0, column = 0, columns = 0;
  if (std::sscanf(line.c_str(), "Matching block [%d/%d, %d/%d]", &row, &rows, &column, &columns) !=
          4 ||
      rows <= 0 || columns <= 0) {
    return -1;
  }
  return static_cast<double>((row - 1) * columns + column) / (rows * columns);
}

// "Matching image [5/24] in 0.3s".
double SequentialProgress(const std::string& line) {
  int done = 0, total = 0;
  if (std::sscanf(line.c_str(), "Matching image [%d/%d]", &done, &total) != 2) return -1;
  return total > 0 ? static_cast<double>(done) / total : -1;
}

// "Registering image #7 (5)": the 5th photo of the current model. A later
// model restarts the count, so progress keeps its highest value.
ProgressParser MapperProgress(int num_photos) {
  return [num_photos, best = 0.0](const std::string& line) mutable {
    int image_id = 0, registered = 0;
    if (std::sscanf(line.c_str(), "Registering image #%d (%d)", &image_id, &registered) != 2) {
      return -1.0;
    }
    best = std::max(best, static_cast<double>(registered) / num_photos);
    return best;
  };
}

// ---------------------------------------------------------------------------
// Child processes.

struct CommandOutcome {
  int exit_code = -1;    // exit status, or -1 if killed by a signal
  int term_signal = 0;   // the signal that ended it, or 0
  bool stalled = false;  // stopped by us: no output and no CPU time for stall_seconds
  double seconds = 0.0;
  std::deque<std::string> last_lines;  // the end of its output
};

// The environment of COLMAP: ours, with Qt told there is no display.
std::vector<std::string> ChildEnvironment() {
  constexpr char kQtPlatform[] = "QT_QPA_PLATFORM=";
  std::vector<std::string> environment;
  for (char** entry = environ; entry != nullptr && *entry != nullptr; ++entry) {
    if (std::strncmp(*entry, kQtPlatform, sizeof(kQtPlatform) - 1) != 0) {
      environment.emplace_back(*entry);
    }
  }
  environment.push_back(std::string(kQtPlatform) + "offscreen");
  return environment;
}

std::vector<char*> CStrings(std::vector<std::string>& strings) {
  std::vector<char*> pointers;
  for (std::string& text : strings) pointers.push_back(text.data());
  pointers.push_back(nullptr);
  return pointers;
}

// One running command, in its own process group, its stdout and stderr on one
// pipe. The destructor kills the group and reaps the child if it still runs,
// so an exception (Cancelled included) never leaves COLMAP behind.
class ChildProcess {
 public:
  ChildProcess(const fs::path& executable, std::vector<std::string> argv);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Appends what the child wrote (waiting at most `max_wait_ms`) to `output`;
  // false once the child closed its output.
  bool Read(int max_wait_ms, std::string* output);
  // True (and the status set) once the child has exited.
  bool Exited(int* status);
  void KillGroup();
  // CPU time the child has used so far (all its threads), in clock ticks;
  // -1 if the system does not say.
  int64_t CpuTicks() const;

 private:
  pid_t pid_ = -1;
  int read_fd_ = -1;
  bool reaped_ = false;
};

ChildProcess::ChildProcess(const fs::path& executable, std::vector<std::string> argv) {
  int pipe_fds[2];
  SYLVA_CHECK(pipe2(pipe_fds, O_CLOEXEC) == 0) << "pipe2: " << std::strerror(errno);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  // Its own process group (so that a kill reaches anything it starts), no
  // blocked signals, and default handlers for those a front end may catch.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  posix_spawnattr_setpgroup(&attributes, 0);
  sigset_t signals;
  sigemptyset(&signals);
  posix_spawnattr_setsigmask(&attributes, &signals);
  for (const int signal : {SIGINT, SIGTERM, SIGQUIT, SIGPIPE, SIGHUP}) sigaddset(&signals, signal);
  posix_spawnattr_setsigdefault(&attributes, &signals);

  std::vector<std::string> environment = ChildEnvironment();
  const std::vector<char*> argv_pointers = CStrings(argv);
  const std::vector<char*> environment_pointers = CStrings(environment);
  const int error = posix_spawn(&pid_, executable.c_str(), &actions, &attributes,
                                argv_pointers.data(), environment_pointers.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(pipe_fds[1]);
  read_fd_ = pipe_fds[0];
  if (error != 0) {
    close(read_fd_);
    SYLVA_INPUT_ERROR("Colmap.executable")
        << "cannot run " << executable << ": " << std::strerror(error);
  }
}

ChildProcess::~ChildProcess() {
  if (!reaped_) {
    KillGroup();
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (read_fd_ >= 0) close(read_fd_);
}

void ChildProcess::KillGroup() {
  if (!reaped_) kill(-pid_, SIGKILL);
}

bool ChildProcess::Read(int max_wait_ms, std::string* output) {
  if (read_fd_ < 0) return false;
  pollfd fd = {read_fd_, POLLIN, 0};
  if (poll(&fd, 1, max_wait_ms) <= 0) return true;
  char buffer[65536];
  const ssize_t count = read(read_fd_, buffer, sizeof(buffer));
  if (count > 0) {
    output->append(buffer, static_cast<size_t>(count));
    return true;
  }
  if (count < 0 && errno == EINTR) return true;
  close(read_fd_);
  read_fd_ = -1;
  return false;
}

bool ChildProcess::Exited(int* status) {
  if (reaped_) return true;
  const pid_t done = waitpid(pid_, status, WNOHANG);
  // ECHILD: the host ignores SIGCHLD, so children are reaped unseen; the
  // exit status is lost (reported as success, the model check follows).
  if (done == pid_ || (done < 0 && errno == ECHILD)) reaped_ = true;
  return reaped_;
}

int64_t ChildProcess::CpuTicks() const {
  std::ifstream stat("/proc/" + std::to_string(pid_) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return -1;
  // "pid (name) state ppid ...": utime and stime are fields 14 and 15.
  const size_t name_end = text.rfind(')');
  if (name_end == std::string::npos) return -1;
  std::istringstream fields(text.substr(name_end + 1));
  std::string field;
  int64_t ticks = 0;
  for (int index = 3; index <= 15; ++index) {
    if (!(fields >> field)) return -1;
    if (index >= 14) ticks += std::strtoll(field.c_str(), nullptr, 10);
  }
  return ticks;
}

// Splits complete lines (ended by '\n' or '\r') off the front of `pending`.

std::vector<std::string> TakeLines(std::string* pending) {
  std::vector<std::string> lines;
  size_t start = 0;
  for (size_t i = 0; i < pending->size(); ++i) {
    const char c = (*pending)[i];
    if (c != '\n' && c != '\r') continue;
    if (i > start) lines.push_back(pending->substr(start, i - start));
    start = i + 1;
  }
  pending->erase(0, start);
  return lines;
}

// Runs one COLMAP command to its end: its output goes to `log`, progress
// parsed from it to `task`. Throws Cancelled (after killing it) on request.
// A command silent and idle (no CPU time) for `stall_seconds` (> 0) is
// killed and marked stalled.
CommandOutcome RunCommand(const fs::path& executable, const std::vector<std::string>& argv,
                          double stall_seconds, std::ofstream* log, const ProgressParser& parse,
                          ProgressTask* task) {
  *log << "\n$";
  for (const std::string& arg : argv) *log << ' ' << arg;
  *log << '\n' << std::flush;
  const Clock::time_point start = Clock::now();
  ChildProcess child(executable, argv);
  CommandOutcome outcome;
  int status = 0;
  std::string pending;
  // COLMAP's threads may report items out of order ("Processed file [4/8]"
  // before "[3/8]"): progress keeps its highest value.
  double reported = 0.0;
  const auto consume = [&](const std::string& text) {
    *log << text << std::flush;
    pending += text;
    for (std::string& line : TakeLines(&pending)) {
      const double fraction = parse(line);
      if (fraction > reported) {
        reported = fraction;
        task->Update(fraction);
      }
      outcome.last_lines.push_back(std::move(line));
      if (outcome.last_lines.size() > kQuotedLogLines) outcome.last_lines.pop_front();
    }
  };
  std::string chunk;
  bool open = true;
  Clock::time_point last_active = Clock::now(), last_cpu_check = last_active;
  int64_t cpu_ticks = child.CpuTicks();
  while (true) {
    task->CheckCancelled();  // ~ChildProcess kills COLMAP on the way out
    chunk.clear();
    if (open) {
      open = child.Read(kPollIntervalMs, &chunk);
    } else {
      poll(nullptr, 0, kPollIntervalMs);
    }
    consume(chunk);
    const Clock::time_point now = Clock::now();
    if (!chunk.empty()) last_active = now;
    if (stall_seconds > 0 && !outcome.stalled &&
        std::chrono::duration<double>(now - last_cpu_check).count() >= kCpuCheckSeconds) {
      last_cpu_check = now;
      const int64_t ticks = child.CpuTicks();
      if (ticks < 0 || ticks != cpu_ticks) last_active = now;  // unknown counts as busy
      cpu_ticks = ticks;
      if (std::chrono::duration<double>(now - last_active).count() >= stall_seconds) {
        *log << "\n[sylva] no output and no CPU time for " << stall_seconds
             << " s: COLMAP has hung and is stopped\n";
        outcome.stalled = true;
        child.KillGroup();
      }
    }
    if (child.Exited(&status)) {
      // What it wrote before exiting; a process it left behind may keep the
      // pipe open, so nothing more is awaited.
      while (open) {
        chunk.clear();
        open = child.Read(0, &chunk);
        if (chunk.empty()) break;
        consume(chunk);
      }
      break;
    }
  }
  if (!pending.empty()) outcome.last_lines.push_back(pending);
  outcome.seconds = SecondsSince(start);
  if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) outcome.term_signal = WTERMSIG(status);
  *log << std::flush;
  return outcome;
}

// ---------------------------------------------------------------------------
// The run.

struct RunContext {
  fs::path executable;
  fs::path photos_dir;
  fs::path database;
  fs::path log_path;
  std::ofstream log;
  std::vector<std::string> photo_names;
  int num_photos = 0;
  std::vector<std::string> notes;  // for ColmapResult::notes
};

std::string FormatSeconds(double seconds) {
  std::ostringstream text;
  text << seconds << " s";
  return text.str();
}

// Removes a COLMAP database and SQLite's journal files beside it.
void RemoveDatabase(const fs::path& database) {
  for (const char* suffix : {"", "-shm", "-wal", "-journal"})
    fs::remove(database.string() + suffix);
}

std::string JoinLines(const std::deque<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += "\n  | " + line;
  return text;
}

[[noreturn]] void ThrowRegistrationError(const RunContext& context, const std::string& message,
                                         const CommandOutcome* outcome) {
  std::string text = message;
  if (outcome != nullptr && !outcome->last_lines.empty()) {
    text += "\nlast lines of COLMAP's output:" + JoinLines(outcome->last_lines);
  }
  text += "\nfull log: " + context.log_path.string();
  throw RegistrationError(context.photos_dir.string(), text, context.log_path);
}

bool OutputMentions(const CommandOutcome& outcome, const std::string& text) {
  return std::any_of(outcome.last_lines.begin(), outcome.last_lines.end(),
                     [&](const std::string& line) { return line.find(text) != std::string::npos; });
}

// A command's options, as (--name, value) pairs.
using Flags = std::vector<std::pair<std::string, std::string>>;

// Flags every command gets: the seed, and all output on stderr (glog would
// otherwise write log files into /tmp), without Ceres' per-iteration lines.
Flags CommonFlags(const ColmapOptions& options) {
  return {{"--random_seed", std::to_string(options.random_seed)},
          {"--log_to_stderr", "1"},
          {"--log_level", "0"}};
}

Flags ExtractionFlags(const RunContext& context, const fs::path& image_list,
                      const fs::path& masks_dir, bool single_camera, const ColmapOptions& options) {
  Flags flags = {{"--database_path", context.database.string()},
                 {"--image_path", context.photos_dir.string()},
                 {"--image_list_path", image_list.string()},
                 {"--ImageReader.camera_model", options.camera_model},
                 {"--ImageReader.single_camera", single_camera ? "1" : "0"},
                 {"--SiftExtraction.use_gpu", "0"},
                 {"--SiftExtraction.num_threads", std::to_string(options.num_threads)},
                 {"--SiftExtraction.max_image_size", std::to_string(options.max_image_size)},
                 {"--SiftExtraction.max_num_features", std::to_string(options.max_num_features)}};
  if (options.use_masks) flags.emplace_back("--ImageReader.mask_path", masks_dir.string());
  return flags;
}

// `guided`: the second matching pass (see RematchAndMap) also matches
// guided by each pair's verified geometry.
Flags MatchingFlags(const RunContext& context, const std::string& matcher,
                    const ColmapOptions& options, bool guided) {
  Flags flags = {{"--database_path", context.database.string()},
                 {"--SiftMatching.use_gpu", "0"},
                 {"--SiftMatching.num_threads", std::to_string(options.num_threads)},
                 {"--SiftMatching.guided_matching", guided ? "1" : "0"}};
  if (matcher == "sequential") {
    flags.emplace_back("--SequentialMatching.overlap", std::to_string(options.sequential_overlap));
    flags.emplace_back("--SequentialMatching.loop_detection", "0");
  }
  return flags;
}

// `relaxed`: a retry's thresholds (see kRelaxedMapper).
Flags MappingFlags(const RunContext& context, const fs::path& image_list,
                   const fs::path& sparse_dir, const ColmapOptions& options, bool relaxed) {
  Flags flags = {{"--database_path", context.database.string()},
                 {"--image_path", context.photos_dir.string()},
                 {"--image_list_path", image_list.string()},
                 {"--output_path", sparse_dir.string()},
                 {"--Mapper.num_threads", std::to_string(options.num_threads)},
                 {"--Mapper.min_model_size", std::to_string(kMinModelSize)}};
  if (relaxed) flags.insert(flags.end(), std::begin(kRelaxedMapper), std::end(kRelaxedMapper));
  return flags;
}

// Runs COLMAP's `command` with `args`; throws RegistrationError if it fails.
// Reports the task done at the end unless `report_done` is false (a step that
// may be run again, whose progress would then fall back).
CommandOutcome RunStep(RunContext* context, const std::string& command, Flags flags,
                       const ColmapOptions& options, const ProgressParser& parse, ProgressTask task,
                       bool report_done = true) {
  const Flags common = CommonFlags(options);
  flags.insert(flags.end(), common.begin(), common.end());
  std::vector<std::string> argv = {context->executable.string(), command};
  for (const auto& [name, value] : flags) argv.insert(argv.end(), {name, value});
  CommandOutcome outcome =
      RunCommand(context->executable, argv, options.stall_seconds, &context->log, parse, &task);
  const std::string hung = "COLMAP " + command + " hung (no output and no CPU time for " +
                           FormatSeconds(options.stall_seconds) + ")";
  // Hung: once more, unless it is the mapper (its retries are MapWithRetries').
  if (outcome.stalled && command != "mapper") {
    context->notes.push_back(hung + " and was run again");
    SYLVA_LOG(kWarning) << context->notes.back();
    if (command == "feature_extractor") RemoveDatabase(context->database);
    const double hung_seconds = outcome.seconds;
    outcome =
        RunCommand(context->executable, argv, options.stall_seconds, &context->log, parse, &task);
    outcome.seconds += hung_seconds;
  }
  if (outcome.stalled) {
    ThrowRegistrationError(
        *context, hung + " and was stopped; run again, or raise Colmap.stall_seconds", &outcome);
  }
  if (outcome.term_signal != 0) {
    ThrowRegistrationError(*context,
                           "COLMAP " + command + " crashed (signal " +
                               std::to_string(outcome.term_signal) + ", " +
                               strsignal(outcome.term_signal) + ")",
                           &outcome);
  }
  if (outcome.exit_code != 0) {
    std::string message =
        "COLMAP " + command + " failed with exit code " + std::to_string(outcome.exit_code);
    if (command == "mapper" && OutputMentions(outcome, "No images with matches")) {
      message = "COLMAP found no matches between the " + std::to_string(context->num_photos) +
                " photos (too little overlap or texture?), so no model could be built";
    }
    ThrowRegistrationError(*context, message, &outcome);
  }
  if (report_done) task.Update(1.0);
  return outcome;
}

std::string ChooseMatcher(const ColmapOptions& options, int num_photos) {
  if (options.matcher != "auto") return options.matcher;
  return num_photos <= options.exhaustive_max_photos ? "exhaustive" : "sequential";
}

// Checks every photo (and mask) and returns whether all photos have one size.
bool CheckPhotos(const fs::path& photos_dir, const std::vector<std::string>& photo_names,
                 const fs::path& masks_dir, bool use_masks) {
  SYLVA_CHECK_INPUT(!photo_names.empty(), photos_dir.string()) << "no photos to register";
  SYLVA_CHECK_INPUT(fs::is_directory(photos_dir), photos_dir.string())
      << "the photo folder does not exist";
  std::vector<std::string> sorted = photo_names;
  std::sort(sorted.begin(), sorted.end());
  const auto duplicate = std::adjacent_find(sorted.begin(), sorted.end());
  SYLVA_CHECK_INPUT(duplicate == sorted.end(), photos_dir.string())
      << "photo '" << *duplicate << "' is listed twice";
  SYLVA_CHECK_INPUT(!use_masks || fs::is_directory(masks_dir), "Colmap.use_masks")
      << "masks were asked for, but the mask folder '" << masks_dir.string() << "' does not exist";
  bool same_size = true;
  ImageHeader first;
  for (size_t i = 0; i < photo_names.size(); ++i) {
    const fs::path name(photo_names[i]);
    SYLVA_CHECK_INPUT(!photo_names[i].empty() && name.is_relative() &&
                          photo_names[i].find('\n') == std::string::npos &&
                          std::find(name.begin(), name.end(), "..") == name.end(),
                      photos_dir.string())
        << "photo name '" << photo_names[i]
        << "' must be a path inside the photo folder (relative, without '..')";
    const ImageHeader header = ReadImageHeader(photos_dir / photo_names[i]);
    if (i == 0) first = header;
    same_size = same_size && header.width == first.width && header.height == first.height;
    if (!use_masks) continue;
    const fs::path mask_path = ColmapMaskPath(masks_dir, photo_names[i]);
    const ImageHeader mask = ReadImageHeader(mask_path);
    SYLVA_CHECK_INPUT(mask.width == header.width && mask.height == header.height,
                      mask_path.string())
        << "the mask is " << mask.width << "x" << mask.height << " but its photo is "
        << header.width << "x" << header.height;
  }
  return same_size;
}

// Removes what an earlier run left, so COLMAP starts afresh.
void PrepareWorkspace(const fs::path& workspace, const std::vector<std::string>& photo_names) {
  fs::create_directories(workspace);
  RemoveDatabase(workspace / kDatabaseName);
  fs::remove_all(workspace / kSparseFolder);
  fs::remove_all(workspace / kRetryFolder);
  fs::create_directories(workspace / kSparseFolder);
  std::string list;
  for (const std::string& name : photo_names) list += name + "\n";
  AtomicWriteString(workspace / kImageListName, list);
}

// The models in `sparse_dir` (folders 0, 1, ...) in COLMAP's order.
std::vector<ImageSet> ReadModels(const fs::path& sparse_dir) {
  std::vector<std::pair<int, fs::path>> folders;
  for (const fs::directory_entry& entry : fs::directory_iterator(sparse_dir)) {
    const std::string name = entry.path().filename().string();
    const bool numeric = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c)) != 0;
    });
    if (entry.is_directory() && numeric && IsColmapModelDir(entry.path())) {
      folders.emplace_back(std::stoi(name), entry.path());
    }
  }
  std::sort(folders.begin(), folders.end());
  std::vector<ImageSet> models;
  for (const auto& folder : folders) models.push_back(ReadColmapModel(folder.second));
  return models;
}

int LargestModelSize(const std::vector<ImageSet>& models) {
  int largest = 0;
  for (const ImageSet& model : models) largest = std::max(largest, model.NumViews());
  return largest;
}

// Keeps the largest model (the first of equals); the others' photos count as
// unregistered.
void TakeLargestModel(std::vector<ImageSet> models, const std::vector<std::string>& photo_names,
                      ColmapResult* result) {
  result->num_models = static_cast<int>(models.size());
  const auto largest = std::max_element(
      models.begin(), models.end(),
      [](const ImageSet& a, const ImageSet& b) { return a.NumViews() < b.NumViews(); });
  result->cameras = std::move(*largest);
  for (const std::string& name : photo_names) {
    if (result->cameras.FindView(name) < 0) result->unregistered.push_back(name);
  }
}

void LogPartialSuccess(const ColmapResult& result) {
  if (result.num_models > 1) {
    SYLVA_LOG(kWarning) << "COLMAP built " << result.num_models << " separate models; keeping the "
                        << "largest (" << result.cameras.NumViews() << " photos), the photos of "
                        << "the others count as unregistered";
  }
  if (!result.unregistered.empty()) {
    SYLVA_LOG(kWarning) << "COLMAP registered " << result.cameras.NumViews() << " of "
                        << result.cameras.NumViews() + result.unregistered.size()
                        << " photos; not registered: " << result.unregistered.size() << " (first: '"
                        << result.unregistered.front() << "')";
  }
}

// Runs the mapper, and again with other seeds and relaxed thresholds (up to
// options.mapper_attempts runs) while photos stay unregistered: incremental
// mapping depends on its initial pair and RANSAC draws, and costs little
// beside matching. The attempt that registers the most photos is kept in
// <workspace>/sparse and in `result` (an earlier one if `result` already
// holds a better model). A retry that fails ends the retries; the first must
// succeed unless `result` already holds a model. `first_seed` offsets the
// seeds. Returns the kept attempt's outcome (empty if none was kept).
CommandOutcome MapWithRetries(RunContext* context, const fs::path& image_list,
                              const fs::path& workspace, const ColmapOptions& options,
                              int first_seed, const ProgressTask& task, ColmapResult* result) {
  const fs::path sparse_dir = workspace / kSparseFolder;
  const fs::path retry_dir = workspace / kRetryFolder;
  const ProgressParser progress = MapperProgress(context->num_photos);  // kept across attempts
  CommandOutcome kept;
  const bool had_model = result->cameras.NumViews() > 0;
  for (int attempt = 0; attempt < options.mapper_attempts; ++attempt) {
    const bool first = attempt == 0 && !had_model;
    const fs::path output = first ? sparse_dir : retry_dir;
    fs::remove_all(output);
    fs::create_directories(output);
    ColmapOptions seeded = options;
    seeded.random_seed = options.random_seed + first_seed + attempt;
    const bool relaxed = first_seed + attempt > 0;
    CommandOutcome outcome;
    try {
      outcome =
          RunStep(context, "mapper", MappingFlags(*context, image_list, output, seeded, relaxed),
                  seeded, progress, task, /*report_done=*/false);
    } catch (const RegistrationError&) {
      if (first) throw;
      result->notes.push_back("COLMAP mapper retry " + std::to_string(first_seed + attempt) +
                              " failed; the earlier model is kept (see " +
                              context->log_path.string() + ")");
      SYLVA_LOG(kWarning) << result->notes.back();
      break;
    }
    result->mapping_seconds += outcome.seconds;
    ++result->mapper_runs;
    std::vector<ImageSet> models = ReadModels(output);
    const int registered = models.empty() ? 0 : LargestModelSize(models);
    if (first || registered > result->cameras.NumViews()) {
      if (!first) {
        fs::remove_all(sparse_dir);
        fs::rename(output, sparse_dir);
      }
      result->cameras = ImageSet();
      result->unregistered.clear();
      if (!models.empty()) TakeLargestModel(std::move(models), context->photo_names, result);
      result->relaxed_mapping = relaxed;
      kept = std::move(outcome);
    }
    fs::remove_all(retry_dir);
    if (result->cameras.NumViews() == context->num_photos) break;
  }
  // Done only now: a retry's progress starts again from the photos its model
  // holds, below a finished attempt's 1.0.
  ProgressTask(task).Update(1.0);
  return kept;
}

}  // namespace

std::string ColmapResult::BriefReport() const {
  std::ostringstream text;
  text.precision(3);
  const size_t total = cameras.views.size() + unregistered.size();
  text << "COLMAP registered " << cameras.NumViews() << " of " << total << " photos (" << num_models
       << (num_models == 1 ? " model; " : " models; ") << matcher << " matching; extraction "
       << extraction_seconds << " s, matching " << matching_seconds << " s, mapping "
       << mapping_seconds << " s; sylva " << sylva_seconds << " s)";
  return text.str();
}

fs::path ColmapMaskPath(const fs::path& masks_dir, const std::string& photo_name) {
  return masks_dir / (photo_name + ".png");
}

FloatImage ColmapMaskFromMatte(const FloatImage& matte, float threshold, int dilation_px) {
  SYLVA_CHECK(matte.channels() == 1) << "a matte has one channel, got " << matte.channels();
  SYLVA_CHECK(dilation_px >= 0) << "dilation must be >= 0";
  const int width = matte.width(), height = matte.height();
  // Square dilation as two running-maximum passes (rows, then columns).
  FloatImage rows(width, height, 1), mask(width, height, 1);
  for (int y = 0; y < height; ++y) {
    int last_on = -(dilation_px + 1) - 1;  // last foreground x seen
    std::vector<int> next_on(width + 1, width + dilation_px + 1);
    for (int x = width - 1; x >= 0; --x) {
      next_on[x] = matte.at(x, y) > threshold ? x : next_on[x + 1];
    }
    for (int x = 0; x < width; ++x) {
      if (matte.at(x, y) > threshold) last_on = x;
      const bool on = x - last_on <= dilation_px || next_on[x] - x <= dilation_px;
      rows.at(x, y) = on ? 1.0f : 0.0f;
    }
  }
  for (int x = 0; x < width; ++x) {
    int last_on = -(dilation_px + 1) - 1;
    std::vector<int> next_on(height + 1, height + dilation_px + 1);
    for (int y = height - 1; y >= 0; --y) next_on[y] = rows.at(x, y) > 0 ? y : next_on[y + 1];
    for (int y = 0; y < height; ++y) {
      if (rows.at(x, y) > 0) last_on = y;
      const bool on = y - last_on <= dilation_px || next_on[y] - y <= dilation_px;
      mask.at(x, y) = on ? 1.0f : 0.0f;
    }
  }
  return mask;
}

fs::path FindColmapExecutable(const std::string& executable) {
  const auto runnable = [](const fs::path& path) {
    return fs::is_regular_file(path) && access(path.c_str(), X_OK) == 0;
  };
  const char* kHint = "install the Debian package colmap, or set Colmap.executable";
  if (executable.find('/') != std::string::npos) {
    SYLVA_CHECK_INPUT(runnable(executable), "Colmap.executable")
        << "colmap not found: '" << executable << "' is not an executable file; " << kHint;
    return executable;
  }
  const char* path_variable = std::getenv("PATH");
  std::istringstream folders(path_variable != nullptr ? path_variable : "");
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    const fs::path candidate = fs::path(folder.empty() ? "." : folder) / executable;
    if (runnable(candidate)) return candidate;
  }
  SYLVA_INPUT_ERROR("Colmap.executable")
      << "colmap not found: no '" << executable << "' in PATH; " << kHint;
  return {};
}

namespace {

// The second pass when too few photos registered: guided matching from the
// extracted features (the database restored by the caller), then the
// mapper's attempts again; `mapping` becomes the new outcome if it kept a
// model.
void MatchAndMapAgain(RunContext* context, const fs::path& image_list, const fs::path& workspace,
                      const ColmapOptions& options, const ProgressParser& matching_progress,
                      const ProgressTask& matching, const ProgressTask& mapping_task,
                      CommandOutcome* mapping, ColmapResult* result) {
  result->notes.push_back("COLMAP registered only " + std::to_string(result->cameras.NumViews()) +
                          " of " + std::to_string(context->num_photos) +
                          " photos at first; matched again (guided) and mapped again");
  SYLVA_LOG(kWarning) << result->notes.back();
  result->matching_seconds += RunStep(context, result->matcher + "_matcher",
                                      MatchingFlags(*context, result->matcher, options, true),
                                      options, matching_progress, matching)
                                  .seconds;
  ++result->matching_runs;
  CommandOutcome again = MapWithRetries(context, image_list, workspace, options,
                                        options.mapper_attempts, mapping_task, result);
  if (again.exit_code == 0) *mapping = std::move(again);  // a model was kept from it
}

// Throws the registration error (with COLMAP's log) when no model or fewer
// than kMinRegisteredPhotos photos came out.
void CheckEnoughRegistered(const RunContext& context, const ColmapResult& result,
                           CommandOutcome* mapping) {
  if (result.cameras.NumViews() == 0) {
    ThrowRegistrationError(context,
                           "COLMAP built no model: no pair of the " +
                               std::to_string(context.num_photos) +
                               " photos has enough matches to start one (too little overlap "
                               "or texture?)",
                           mapping);
  }
  if (result.cameras.NumViews() < kMinRegisteredPhotos) {
    ThrowRegistrationError(context,
                           "COLMAP registered only " + std::to_string(result.cameras.NumViews()) +
                               " of " + std::to_string(context.num_photos) +
                               " photos; at least 2 are needed",
                           mapping);
  }
}

}  // namespace

ColmapResult RunColmap(const fs::path& photos_dir, const std::vector<std::string>& photo_names,
                       const fs::path& masks_dir, const fs::path& workspace,
                       const ColmapOptions& options, ProgressReporter* progress) {
  const Clock::time_point start = Clock::now();
  options.Check();
  RunContext context;
  context.executable = FindColmapExecutable(options.executable);
  context.photos_dir = photos_dir;
  context.photo_names = photo_names;
  context.num_photos = static_cast<int>(photo_names.size());
  const bool same_size = CheckPhotos(photos_dir, photo_names, masks_dir, options.use_masks);

  PrepareWorkspace(workspace, photo_names);
  context.database = workspace / kDatabaseName;
  context.log_path = workspace / kLogName;
  context.log.open(context.log_path, std::ios::trunc);
  SYLVA_CHECK_INPUT(context.log.good(), context.log_path.string()) << "cannot write the log";
  const fs::path image_list = workspace / kImageListName;
  const fs::path sparse_dir = workspace / kSparseFolder;

  ColmapResult result;
  result.log_path = context.log_path;
  result.matcher = ChooseMatcher(options, context.num_photos);
  result.single_camera = options.single_camera && same_size;
  const ProgressTask task(progress, "register: COLMAP");
  const ProgressTask extraction =
      task.SubTask("register: COLMAP feature extraction", 0.0, kExtractionEnd);
  const ProgressTask matching =
      task.SubTask("register: COLMAP matching", kExtractionEnd, kMatchingEnd);
  const ProgressTask mapping_task = task.SubTask("register: COLMAP mapping", kMatchingEnd, 1.0);
  const ProgressParser matching_progress =
      result.matcher == "exhaustive" ? ExhaustiveProgress : SequentialProgress;

  result.extraction_seconds =
      RunStep(&context, "feature_extractor",
              ExtractionFlags(context, image_list, masks_dir, result.single_camera, options),
              options, ExtractionProgress, extraction)
          .seconds;
  const fs::path features_database = workspace / kFeaturesDatabaseName;
  std::error_code ec;
  const bool can_rematch =
      fs::copy_file(context.database, features_database, fs::copy_options::overwrite_existing, ec);
  result.matching_seconds = RunStep(&context, result.matcher + "_matcher",
                                    MatchingFlags(context, result.matcher, options, false), options,
                                    matching_progress, matching)
                                .seconds;
  CommandOutcome mapping =
      MapWithRetries(&context, image_list, workspace, options, 0, mapping_task, &result);

  // Too few photos registered: COLMAP's matching (its RANSAC in worker
  // threads is not seeded) may have come out weak; match again from the
  // features, guided, and map again.
  if (can_rematch && result.cameras.NumViews() < options.rematch_below * context.num_photos) {
    fs::copy_file(features_database, context.database, fs::copy_options::overwrite_existing);
    MatchAndMapAgain(&context, image_list, workspace, options, matching_progress, matching,
                     mapping_task, &mapping, &result);
  }
  fs::remove(features_database, ec);
  result.notes.insert(result.notes.begin(), context.notes.begin(), context.notes.end());
  result.colmap_seconds =
      result.extraction_seconds + result.matching_seconds + result.mapping_seconds;
  CheckEnoughRegistered(context, result, &mapping);
  LogPartialSuccess(result);
  result.sylva_seconds = SecondsSince(start) - result.colmap_seconds;
  return result;
}

}  // namespace sylva
