#include "core/util/progress.h"

#include <algorithm>

#include "core/util/check.h"

namespace sylva {
namespace {

// Updates closer together than this are dropped (except the final one).
constexpr std::chrono::milliseconds kMinUpdateInterval(100);

}  // namespace

ProgressTask::ProgressTask(ProgressReporter* reporter, std::string name, double begin, double end)
    : reporter_(reporter), name_(std::move(name)), begin_(begin), end_(end) {}

void ProgressTask::Update(double fraction) {
  CheckCancelled();
  if (reporter_ == nullptr) return;
  const auto now = std::chrono::steady_clock::now();
  if (fraction < 1.0 && now - last_update_ < kMinUpdateInterval) return;
  last_update_ = now;
  fraction = std::clamp(fraction, 0.0, 1.0);
  reporter_->Update(name_, begin_ + (end_ - begin_) * fraction);
}

void ProgressTask::CheckCancelled() const {
  if (reporter_ != nullptr && reporter_->CancelRequested()) throw Cancelled();
}

ProgressTask ProgressTask::SubTask(std::string name, double sub_begin, double sub_end) const {
  const double span = end_ - begin_;
  return ProgressTask(reporter_, std::move(name), begin_ + span * sub_begin,
                      begin_ + span * sub_end);
}

}  // namespace sylva
