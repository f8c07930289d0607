// Progress reporting and cancellation for long operations.
//
// Long-running algorithms take a `ProgressReporter*` (may be null). They do not
// call the reporter directly but through a ProgressTask, which maps the task's
// own [0, 1] range into a sub-range of the whole run, rate-limits updates, and
// throws Cancelled when the reporter asks to stop. Front ends implement the
// reporter: the CLI draws a line on stderr, the app a progress bar with Cancel.
// (In the spirit of OpenVDB's interrupter and COLMAP's controllers.)
#ifndef SYLVA_CORE_UTIL_PROGRESS_H_
#define SYLVA_CORE_UTIL_PROGRESS_H_

#include <atomic>
#include <chrono>
#include <string>
#include <string_view>

namespace sylva {

class ProgressReporter {
 public:
  virtual ~ProgressReporter() = default;
  // `task` names what is running ("density: solve"); `fraction` in [0, 1].
  // Called from the thread that drives the operation, never concurrently.
  virtual void Update(std::string_view task, double fraction) = 0;
  // Polled by operations between units of work; may be called from any thread.
  virtual bool CancelRequested() const { return cancel_.load(std::memory_order_relaxed); }
  void RequestCancel() { cancel_.store(true, std::memory_order_relaxed); }

 private:
  std::atomic<bool> cancel_{false};
};

// One step of a long operation, occupying [begin, end] of its reporter's range.
class ProgressTask {
 public:
  ProgressTask(ProgressReporter* reporter, std::string name, double begin = 0.0, double end = 1.0);
  // Reports `fraction` (in [0, 1]) of this task. Throws Cancelled if requested.
  // Cheap enough to call every few milliseconds.
  void Update(double fraction);
  // Throws Cancelled if requested, without reporting progress. Thread-safe.
  void CheckCancelled() const;
  // A sub-task covering [sub_begin, sub_end] of this task's range.
  ProgressTask SubTask(std::string name, double sub_begin, double sub_end) const;

 private:
  ProgressReporter* reporter_;
  std::string name_;
  double begin_;
  double end_;
  std::chrono::steady_clock::time_point last_update_{};
};

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_PROGRESS_H_
