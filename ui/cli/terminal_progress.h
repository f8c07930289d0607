// Progress on stderr for the CLI: a rewritten line on a terminal, otherwise
// one line per task and per tenth of progress (readable in batch logs).
#ifndef SYLVA_UI_CLI_TERMINAL_PROGRESS_H_
#define SYLVA_UI_CLI_TERMINAL_PROGRESS_H_

#include <string>

#include "core/util/progress.h"

namespace sylva {

class TerminalProgress : public ProgressReporter {
 public:
  TerminalProgress();
  ~TerminalProgress() override;
  void Update(std::string_view task, double fraction) override;
  // Ends an open progress line.
  void Finish();

  // Routes SIGINT to RequestCancel() of `reporter` (a second SIGINT kills).
  static void InstallInterruptHandler(ProgressReporter* reporter);

 private:
  bool is_terminal_;
  bool line_open_ = false;
  std::string last_task_;
  int last_tenth_ = -1;
};

}  // namespace sylva

#endif  // SYLVA_UI_CLI_TERMINAL_PROGRESS_H_
