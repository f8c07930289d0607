// Runs a program as a real child process (fork + exec, no shell) and captures
// its stdout and stderr separately, for end-to-end tests of the sylva binary.
//
//   SubprocessResult r = RunSubprocess({sylva, "run", project});
//   EXPECT_EQ(r.exit_code, 2) << r.Describe();
//
// A Subprocess can also be driven while it runs (wait for a line of output,
// send it a signal). Not thread-safe; one object per child.
#ifndef SYLVA_TESTS_E2E_SUBPROCESS_H_
#define SYLVA_TESTS_E2E_SUBPROCESS_H_

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace sylva {

struct SubprocessResult {
  int exit_code = -1;      // the child's exit status, or -1 if killed by a signal
  int term_signal = 0;     // the signal that killed the child, or 0
  bool timed_out = false;  // killed by us (SIGKILL) when the timeout expired
  double seconds = 0.0;    // wall time from start to exit
  std::string out;         // everything written to stdout
  std::string err;         // everything written to stderr

  // The command's outcome and output, for test failure messages.
  std::string Describe() const;
};

class Subprocess {
 public:
  // Starts argv[0] (a path; PATH is not searched) with argv, the parent's
  // environment and stdin from /dev/null. Throws std::runtime_error if the
  // process cannot be created; an exec failure shows as exit code 127.
  explicit Subprocess(const std::vector<std::string>& argv);
  // Kills (SIGKILL) and reaps the child if it still runs.
  ~Subprocess();
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  pid_t pid() const { return pid_; }
  // Sends `signal` to the child (if it has not been reaped).
  void Signal(int signal);
  // Collects output until stderr contains `text`; false if the child closed
  // its output or `timeout_seconds` passed first.
  bool WaitForStderr(const std::string& text, double timeout_seconds);
  // Collects the remaining output and waits for the child to exit; after
  // `timeout_seconds` it is killed and the result says timed_out.
  SubprocessResult Wait(double timeout_seconds);

 private:
  // Reads what is available on the open pipes, waiting at most `max_wait_ms`.
  void Poll(int max_wait_ms);
  void KillAndReap();

  pid_t pid_ = -1;
  int out_fd_ = -1;
  int err_fd_ = -1;
  bool reaped_ = false;
  int status_ = 0;
  std::chrono::steady_clock::time_point start_;
  SubprocessResult result_;
};

// Runs argv to completion (see Subprocess).
SubprocessResult RunSubprocess(const std::vector<std::string>& argv,
                               double timeout_seconds = 120.0);

}  // namespace sylva

#endif  // SYLVA_TESTS_E2E_SUBPROCESS_H_
