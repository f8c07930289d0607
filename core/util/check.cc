#include "core/util/check.h"

#include <exception>

namespace sylva {

namespace {

std::string JoinSourceAndMessage(const std::string& source, const std::string& message) {
  return source.empty() ? message : source + ": " + message;
}

}  // namespace

InputError::InputError(const std::string& source, const std::string& message)
    : Error(JoinSourceAndMessage(source, message)), source_(source), message_(message) {}

namespace internal {

CheckFailure::CheckFailure(const char* file, int line, const char* condition) {
  std::ostringstream prefix;
  prefix << file << ":" << line << ": check failed: " << condition;
  prefix_ = prefix.str();
}

CheckFailure::CheckFailure(std::string source) : is_input_(true), prefix_(std::move(source)) {}

CheckFailure::~CheckFailure() noexcept(false) {
  // Never throw while another exception unwinds the stack.
  if (std::uncaught_exceptions() > 0) return;
  const std::string message = stream_.str();
  if (is_input_) throw InputError(prefix_, message.empty() ? "invalid input" : message);
  throw Error(message.empty() ? prefix_ : prefix_ + ": " + message);
}

}  // namespace internal
}  // namespace sylva
