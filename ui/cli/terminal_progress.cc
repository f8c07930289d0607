#include "ui/cli/terminal_progress.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>

namespace sylva {
namespace {

ProgressReporter* g_interrupt_target = nullptr;

void OnInterrupt(int) {
  if (g_interrupt_target != nullptr) g_interrupt_target->RequestCancel();
  std::signal(SIGINT, SIG_DFL);
}

}  // namespace

TerminalProgress::TerminalProgress() : is_terminal_(isatty(fileno(stderr)) != 0) {}

TerminalProgress::~TerminalProgress() { Finish(); }

void TerminalProgress::Update(std::string_view task, double fraction) {
  const int percent = static_cast<int>(fraction * 100.0 + 0.5);
  if (is_terminal_) {
    std::fprintf(stderr, "\r%-44.*s %3d%%", static_cast<int>(task.size()), task.data(), percent);
    std::fflush(stderr);
    line_open_ = true;
    return;
  }
  const int tenth = percent / 10;
  if (task == last_task_ && tenth == last_tenth_) return;
  last_task_ = std::string(task);
  last_tenth_ = tenth;
  std::fprintf(stderr, "[%.*s] %d%%\n", static_cast<int>(task.size()), task.data(), percent);
}

void TerminalProgress::Finish() {
  if (line_open_) std::fputc('\n', stderr);
  line_open_ = false;
}

void TerminalProgress::InstallInterruptHandler(ProgressReporter* reporter) {
  g_interrupt_target = reporter;
  std::signal(SIGINT, OnInterrupt);
}

}  // namespace sylva
