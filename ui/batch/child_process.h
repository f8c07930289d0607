// A child process whose output goes to a log file, for the batch runner: one
// per tree, so that a tree that crashes (or is killed) cannot take the batch
// with it. POSIX (fork + exec); on Linux the child is killed when the
// process that started it dies, so a killed batch leaves no tree running.
#ifndef SYLVA_UI_BATCH_CHILD_PROCESS_H_
#define SYLVA_UI_BATCH_CHILD_PROCESS_H_

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

class ChildProcess {
 public:
  // Starts argv[0] (a path; PATH is not searched) with `argv`, stdin from
  // /dev/null, stdout and stderr appended to `log_path` (created). In its own
  // process group, so a Ctrl-C at the terminal reaches only the batch, which
  // passes it on (Interrupt()). Throws Error if it cannot start; a failed
  // exec shows as exit code 127.
  ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& log_path);
  // Kills (SIGKILL) and reaps the child if it still runs.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // True once the child has exited (reaps it); does not block.
  bool Poll();
  // After Poll() returned true: the exit code, or -1 if killed by a signal,
  // and that signal (0 if it exited).
  int exit_code() const { return exit_code_; }
  int term_signal() const { return term_signal_; }
  // Sends SIGINT (the child cancels its run cleanly).
  void Interrupt();

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_code_ = -1;
  int term_signal_ = 0;
};

// The path of the running program (/proc/self/exe on Linux).
std::filesystem::path SelfExecutablePath();

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_CHILD_PROCESS_H_
