// Named warnings: what an algorithm did, or could not do, that changes what
// its result means, and that a person must see (a view left out, a matte
// repaired, structure finer than the voxels). Summaries carry them; the CLI
// prints them after the stage's summary, the report lists them, and tests
// and batch summaries look for them by code.
#ifndef SYLVA_CORE_UTIL_WARNING_H_
#define SYLVA_CORE_UTIL_WARNING_H_

#include <string>
#include <utility>
#include <vector>

namespace sylva {

struct Warning {
  Warning() = default;
  Warning(std::string code_in, std::string message_in, std::string subject_in = "")
      : code(std::move(code_in)), message(std::move(message_in)), subject(std::move(subject_in)) {}

  // A stable kebab-case name of the kind of warning ("distrusted-view",
  // "inverted-matte", ...): what scripts and tests match.
  std::string code;
  // What happened and to what, for a person ("view_03.png: its matte ...").
  std::string message;
  // What it is about, when that is one thing: a view's photo name, so that
  // the report can show it beside that view; "" otherwise.
  std::string subject;

  // "[code] message"
  std::string ToString() const { return "[" + code + "] " + message; }
};

// Whether any warning in `warnings` has this code.
inline bool HasWarning(const std::vector<Warning>& warnings, const std::string& code) {
  for (const Warning& warning : warnings) {
    if (warning.code == code) return true;
  }
  return false;
}

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_WARNING_H_
