#include "tests/e2e/subprocess.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace sylva {
namespace {

using Clock = std::chrono::steady_clock;

// Output longer than this is shortened in Describe() (head and tail kept).
constexpr size_t kMaxDescribedOutput = 6000;

std::string Shortened(const std::string& text) {
  if (text.size() <= kMaxDescribedOutput) return text;
  const size_t half = kMaxDescribedOutput / 2;
  return text.substr(0, half) + "\n[... " + std::to_string(text.size() - 2 * half) +
         " bytes ...]\n" + text.substr(text.size() - half);
}

Clock::time_point DeadlineAfter(double seconds) {
  return Clock::now() +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

int MillisecondsUntil(Clock::time_point deadline) {
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<long long>(ms, 0, 100));
}

// In the child, between fork and exec: only async-signal-safe calls.
[[noreturn]] void ExecChild(char* const* args, int out_fd, int err_fd) {
  const int null_fd = open("/dev/null", O_RDONLY);
  if (null_fd < 0 || dup2(null_fd, STDIN_FILENO) < 0 || dup2(out_fd, STDOUT_FILENO) < 0 ||
      dup2(err_fd, STDERR_FILENO) < 0) {
    _exit(127);
  }
  // A clean slate: signals the test process blocks or ignores must reach sylva.
  struct sigaction default_action;
  std::memset(&default_action, 0, sizeof(default_action));
  default_action.sa_handler = SIG_DFL;
  for (const int signal : {SIGINT, SIGTERM, SIGPIPE, SIGQUIT}) {
    sigaction(signal, &default_action, nullptr);
  }
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  execv(args[0], args);
  constexpr char kMessage[] = "subprocess: exec failed\n";
  [[maybe_unused]] const ssize_t ignored = write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  _exit(127);
}

}  // namespace

std::string SubprocessResult::Describe() const {
  std::ostringstream text;
  if (timed_out) {
    text << "timed out (killed) after " << seconds << " s";
  } else if (term_signal != 0) {
    text << "killed by signal " << term_signal << " (" << strsignal(term_signal) << ")";
  } else {
    text << "exit code " << exit_code << " after " << seconds << " s";
  }
  text << "\n--- stdout ---\n"
       << Shortened(out) << "\n--- stderr ---\n"
       << Shortened(err) << "\n--------------";
  return text.str();
}

Subprocess::Subprocess(const std::vector<std::string>& argv) {
  if (argv.empty()) throw std::invalid_argument("Subprocess: empty argv");
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  int out_pipe[2], err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
  if (pipe2(err_pipe, O_CLOEXEC) != 0) {
    close(out_pipe[0]);
    close(out_pipe[1]);
    throw std::runtime_error("pipe2 failed");
  }
  start_ = Clock::now();
  pid_ = fork();
  if (pid_ == 0) ExecChild(args.data(), out_pipe[1], err_pipe[1]);
  close(out_pipe[1]);
  close(err_pipe[1]);
  out_fd_ = out_pipe[0];
  err_fd_ = err_pipe[0];
  if (pid_ < 0) {
    const int error = errno;
    close(out_fd_);
    close(err_fd_);
    throw std::runtime_error(std::string("fork failed: ") + std::strerror(error));
  }
}

Subprocess::~Subprocess() {
  if (!reaped_) KillAndReap();
  if (out_fd_ >= 0) close(out_fd_);
  if (err_fd_ >= 0) close(err_fd_);
}

void Subprocess::Signal(int signal) {
  if (!reaped_) kill(pid_, signal);
}

void Subprocess::KillAndReap() {
  kill(pid_, SIGKILL);
  while (waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  result_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
}

void Subprocess::Poll(int max_wait_ms) {
  pollfd fds[2];
  std::string* sinks[2];
  int* owners[2];
  nfds_t count = 0;
  for (auto [fd, sink] : {std::pair{&out_fd_, &result_.out}, std::pair{&err_fd_, &result_.err}}) {
    if (*fd < 0) continue;
    fds[count] = {*fd, POLLIN, 0};
    sinks[count] = sink;
    owners[count++] = fd;
  }
  if (count == 0 || poll(fds, count, max_wait_ms) <= 0) return;
  for (nfds_t i = 0; i < count; ++i) {
    if (fds[i].revents == 0) continue;
    char buffer[65536];
    const ssize_t n = read(fds[i].fd, buffer, sizeof(buffer));
    if (n > 0) {
      sinks[i]->append(buffer, static_cast<size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      close(*owners[i]);
      *owners[i] = -1;
    }
  }
}

bool Subprocess::WaitForStderr(const std::string& text, double timeout_seconds) {
  const Clock::time_point deadline = DeadlineAfter(timeout_seconds);
  while (result_.err.find(text) == std::string::npos) {
    if (err_fd_ < 0 || Clock::now() >= deadline) return false;
    Poll(MillisecondsUntil(deadline));
  }
  return true;
}

SubprocessResult Subprocess::Wait(double timeout_seconds) {
  const Clock::time_point deadline = DeadlineAfter(timeout_seconds);
  while (!reaped_) {
    if (Clock::now() >= deadline) {
      result_.timed_out = true;
      KillAndReap();
      break;
    }
    if (out_fd_ >= 0 || err_fd_ >= 0) {
      Poll(MillisecondsUntil(deadline));
      continue;
    }
    // Both pipes closed: the child is exiting.
    const pid_t done = waitpid(pid_, &status_, WNOHANG);
    if (done == pid_) {
      reaped_ = true;
      result_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    } else {
      poll(nullptr, 0, MillisecondsUntil(deadline));
    }
  }
  // Whatever the child wrote just before it ended (bounded, in case a
  // grandchild still holds the pipes).
  const auto drain_deadline = Clock::now() + std::chrono::seconds(2);
  while ((out_fd_ >= 0 || err_fd_ >= 0) && Clock::now() < drain_deadline) Poll(100);
  if (WIFEXITED(status_)) result_.exit_code = WEXITSTATUS(status_);
  if (WIFSIGNALED(status_)) result_.term_signal = WTERMSIG(status_);
  return result_;
}

SubprocessResult RunSubprocess(const std::vector<std::string>& argv, double timeout_seconds) {
  Subprocess process(argv);
  return process.Wait(timeout_seconds);
}

}  // namespace sylva
