// Minimal levelled logging to stderr.
//
// SYLVA_LOG(kInfo) << "read " << n << " views";
// The threshold is process-wide (SetLogLevel); messages below it cost only a
// comparison. Thread-safe: each message is written with one call.
#ifndef SYLVA_CORE_UTIL_LOGGING_H_
#define SYLVA_CORE_UTIL_LOGGING_H_

#include <sstream>
#include <string>

namespace sylva {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3, kSilent = 4 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
// Parses "debug", "info", "warning", "error", "silent"; throws InputError.
LogLevel ParseLogLevel(const std::string& name);

namespace internal {

class LogMessage {
 public:
  explicit LogMessage(LogLevel level) : level_(level) {}
  ~LogMessage();
  LogMessage(const LogMessage&) = delete;
  LogMessage& operator=(const LogMessage&) = delete;
  std::ostream& stream() { return stream_; }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};

}  // namespace internal
}  // namespace sylva

#define SYLVA_LOG(level)                                   \
  if (::sylva::LogLevel::level < ::sylva::GetLogLevel()) { \
  } else                                                   \
    ::sylva::internal::LogMessage(::sylva::LogLevel::level).stream()

#endif  // SYLVA_CORE_UTIL_LOGGING_H_
