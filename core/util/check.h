// Errors and checks shared by every sylva module.
//
// Library code never prints-and-continues and never terminates the program:
// it throws. Only main() and the desktop app's event loop turn an exception
// into an exit code or a dialog. Three kinds are distinguished so that front
// ends can react differently:
//   - InputError: the user's data or options are wrong (a corrupt file, a bad
//     option value). The message names the file or option.
//   - Cancelled: the user asked a long operation to stop.
//   - Error: anything else, typically a failed internal check (a bug).
//
// Usage:
//   SYLVA_CHECK(num_views > 0) << "no views";               // throws Error
//   SYLVA_CHECK_INPUT(ok, path) << "expected 4 channels";   // throws InputError
//   SYLVA_DCHECK(i < n);                                    // debug builds only
#ifndef SYLVA_CORE_UTIL_CHECK_H_
#define SYLVA_CORE_UTIL_CHECK_H_

#include <sstream>
#include <stdexcept>
#include <string>

namespace sylva {

// Base of every exception sylva throws.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Bad user input. `source` names the offending file or option (may be empty);
// what() is "source: message".
class InputError : public Error {
 public:
  InputError(const std::string& source, const std::string& message);
  const std::string& source() const { return source_; }
  const std::string& message() const { return message_; }

 private:
  std::string source_;
  std::string message_;
};

// Thrown when a ProgressReporter reports that cancellation was requested.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

namespace internal {

// Collects a message with operator<< and throws from its destructor. Only
// used through the macros below; never hold one in a variable.
class CheckFailure {
 public:
  // Internal check: throws Error("file:line: check failed: cond: message").
  CheckFailure(const char* file, int line, const char* condition);
  // Input check: throws InputError(source, message).
  explicit CheckFailure(std::string source);
  ~CheckFailure() noexcept(false);
  CheckFailure(const CheckFailure&) = delete;
  CheckFailure& operator=(const CheckFailure&) = delete;

  std::ostream& stream() { return stream_; }

 private:
  bool is_input_ = false;
  std::string prefix_;
  std::ostringstream stream_;
};

}  // namespace internal
}  // namespace sylva

#define SYLVA_CHECK(condition) \
  if (condition) {             \
  } else                       \
    ::sylva::internal::CheckFailure(__FILE__, __LINE__, #condition).stream()

#define SYLVA_CHECK_INPUT(condition, source) \
  if (condition) {                           \
  } else                                     \
    ::sylva::internal::CheckFailure(source).stream()

// Throws InputError(source, message) unconditionally.
#define SYLVA_INPUT_ERROR(source) ::sylva::internal::CheckFailure(source).stream()

#ifdef NDEBUG
#define SYLVA_DCHECK(condition) \
  while (false) SYLVA_CHECK(condition)
#else
#define SYLVA_DCHECK(condition) SYLVA_CHECK(condition)
#endif

#endif  // SYLVA_CORE_UTIL_CHECK_H_
