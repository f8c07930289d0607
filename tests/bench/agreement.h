// Whether a benchmark's fast result agrees with its reference
// implementation's (issue 13, item 5): a benchmark is also a smoke test, and
// it must fail on a wrong result, not only on a crash. Each check prints its
// figure beside the tolerance on stdout; a failed one also prints a line
// starting "DISAGREES" on stderr, naming the figure and the tolerance.
#ifndef SYLVA_TESTS_BENCH_AGREEMENT_H_
#define SYLVA_TESTS_BENCH_AGREEMENT_H_

#include <cstdio>
#include <string>
#include <utility>

namespace sylva {

class Agreement {
 public:
  // `against` names what the results are compared with, for the messages.
  explicit Agreement(std::string against = "the reference") : against_(std::move(against)) {}

  // Passes when `value` <= `tolerance` (a distance, a difference). NaN fails.
  bool AtMost(const std::string& figure, double value, double tolerance) {
    return Record(figure, value, "<=", tolerance, value <= tolerance);
  }
  // Passes when `value` >= `tolerance` (an IoU, a share). NaN fails.
  bool AtLeast(const std::string& figure, double value, double tolerance) {
    return Record(figure, value, ">=", tolerance, value >= tolerance);
  }

  bool ok() const { return failures_ == 0; }

  // 0 when every check passed; otherwise 1, after a count on stderr.
  int ExitCode() const {
    if (failures_ == 0) return 0;
    std::fprintf(stderr, "%d of %d agreement checks with %s failed\n", failures_, checks_,
                 against_.c_str());
    return 1;
  }

 private:
  bool Record(const std::string& figure, double value, const char* relation, double tolerance,
              bool pass) {
    ++checks_;
    std::printf("  agreement: %s %.4g (must be %s %.4g): %s\n", figure.c_str(), value, relation,
                tolerance, pass ? "ok" : "DISAGREES");
    std::fflush(stdout);
    if (!pass) {
      ++failures_;
      std::fprintf(stderr, "DISAGREES with %s: %s is %.6g, tolerance %s %.6g\n", against_.c_str(),
                   figure.c_str(), value, relation, tolerance);
    }
    return pass;
  }

  std::string against_;
  int checks_ = 0;
  int failures_ = 0;
};

}  // namespace sylva

#endif  // SYLVA_TESTS_BENCH_AGREEMENT_H_
