#include "core/util/logging.h"

#include <atomic>
#include <cstdio>

#include "core/util/check.h"

namespace sylva {
namespace {

std::atomic<LogLevel> g_log_level{LogLevel::kInfo};

const char* LevelPrefix(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug: ";
    case LogLevel::kWarning:
      return "warning: ";
    case LogLevel::kError:
      return "error: ";
    default:
      return "";
  }
}

}  // namespace

void SetLogLevel(LogLevel level) { g_log_level = level; }
LogLevel GetLogLevel() { return g_log_level; }

LogLevel ParseLogLevel(const std::string& name) {
  if (name == "debug") return LogLevel::kDebug;
  if (name == "info") return LogLevel::kInfo;
  if (name == "warning") return LogLevel::kWarning;
  if (name == "error") return LogLevel::kError;
  if (name == "silent") return LogLevel::kSilent;
  SYLVA_INPUT_ERROR("log level") << "unknown level '" << name
                                 << "' (expected debug, info, warning, error or silent)";
  return LogLevel::kInfo;
}

namespace internal {

LogMessage::~LogMessage() {
  const std::string line = std::string(LevelPrefix(level_)) + stream_.str() + "\n";
  std::fwrite(line.data(), 1, line.size(), stderr);
}

}  // namespace internal
}  // namespace sylva
