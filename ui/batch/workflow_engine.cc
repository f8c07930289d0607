#include "ui/batch/workflow_engine.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "core/util/check.h"
#include "ui/batch/batch_summary.h"
#include "ui/batch/child_process.h"

extern char** environ;

namespace sylva {
namespace {

constexpr int kExitError = 1;
constexpr char kSnakemake[] = "snakemake";

// Runs argv (argv[0] searched on PATH) with this process's output; returns
// its exit code (128 + signal if killed).
int RunAndWait(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, argv[0].c_str(), nullptr, nullptr, args.data(), environ);
  SYLVA_CHECK_INPUT(error == 0, argv[0]) << "cannot start: " << std::strerror(error)
                                         << " (install Snakemake 7: apt-get install snakemake)";
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    SYLVA_CHECK(errno == EINTR) << "waitpid: " << std::strerror(errno);
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Once Snakemake has returned no job runs: a tree still "running" had its
// job die without recording how (killed, crashed, out of memory).
void MarkDeadJobs(const Manifest& manifest, const std::filesystem::path& out_dir) {
  for (const ManifestTree& tree : manifest.trees) {
    const std::filesystem::path path = TreeStatusPath(out_dir, tree.name);
    std::optional<TreeStatus> status = ReadTreeStatus(path);
    if (!status || status->status != "running") continue;
    status->status = "crashed";
    status->error = "its job ended without recording how (killed or crashed; see its log)";
    WriteTreeStatus(path, *status);
  }
}

}  // namespace

std::filesystem::path WorkflowDir() {
  const char* dir = std::getenv("SYLVA_WORKFLOW_DIR");
  return dir != nullptr && *dir != '\0' ? std::filesystem::path(dir)
                                        : std::filesystem::path(SYLVA_WORKFLOW_DIR);
}

std::filesystem::path ResolveProfile(const std::string& profile) {
  std::error_code ec;
  if (profile.find('/') != std::string::npos && std::filesystem::is_directory(profile, ec)) {
    return std::filesystem::absolute(profile);
  }
  const std::filesystem::path named = WorkflowDir() / "profiles" / profile;
  SYLVA_CHECK_INPUT(std::filesystem::is_regular_file(named / "config.yaml", ec), "--profile")
      << "no profile '" << profile << "' (a folder with config.yaml, or local or slurm in "
      << (WorkflowDir() / "profiles").string() << ")";
  return named;
}

std::vector<std::string> SnakemakeArguments(const Manifest& manifest,
                                            const std::filesystem::path& out_dir,
                                            const std::filesystem::path& profile,
                                            const BatchOptions& options) {
  const std::filesystem::path program =
      options.program.empty() ? SelfExecutablePath() : options.program;
  std::vector<std::string> argv = {kSnakemake,
                                   "--snakefile",
                                   (WorkflowDir() / "Snakefile").string(),
                                   "--profile",
                                   profile.string(),
                                   "--directory",
                                   out_dir.string(),
                                   "--config",
                                   "manifest=" + manifest.path.string(),
                                   "out=" + out_dir.string(),
                                   "sylva=" + program.string()};
  std::string extra;
  for (const auto& [key, value] : options.options) {
    extra += (extra.empty() ? "--" : " --") + key + "=" + value;
  }
  if (!options.log_level.empty())
    extra += (extra.empty() ? "" : " ") + ("--log-level " + options.log_level);
  if (!extra.empty()) argv.push_back("options=" + extra);
  return argv;
}

int RunSnakemakeBatch(const Manifest& manifest, const std::filesystem::path& out_dir,
                      const std::filesystem::path& profile, const BatchOptions& options) {
  std::filesystem::create_directories(BatchLogDir(out_dir));
  const int engine_exit = RunAndWait(SnakemakeArguments(manifest, out_dir, profile, options));
  MarkDeadJobs(manifest, out_dir);
  WriteBatchSummary(manifest, out_dir);
  int failed = 0, unfinished = 0;
  for (const ManifestTree& tree : manifest.trees) {
    const TreeStatus status = SummarizeTree(tree, out_dir).status;
    failed += status.status == "failed" || status.status == "crashed";
    unfinished += !status.Finished();
  }
  if (failed > 0) return kBatchExitTreesFailed;
  return engine_exit == 0 && unfinished == 0 ? 0 : kExitError;
}

}  // namespace sylva
