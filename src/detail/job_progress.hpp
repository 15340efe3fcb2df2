/// @file job_progress.hpp
/// @brief A job's plan of stages over the caller's Progress: stage numbers, an overall
/// fraction that never goes back, and one begin per planned stage whatever the stages
/// announce inside themselves.
#pragma once

#include <algorithm>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/progress.hpp"

namespace tpmsfill::detail {

/// One planned stage and its rough share of the job's time.
struct PlannedStage {
  std::string name;
  double weight = 1;
};

/// Stages call begin_stage() (the job's own announcement, from the job's thread); what the
/// stages themselves report through the Progress interface arrives here and is forwarded with
/// the overall fraction. Their own begin() calls are absorbed: the plan already announced the
/// stage.
class JobProgress final : public Progress {
 public:
  JobProgress(Progress* caller, std::vector<PlannedStage> plan)
      : caller_(caller), plan_(std::move(plan)) {
    for (const PlannedStage& s : plan_) total_ += s.weight;
  }

  /// This object when there is a caller to report to, else null (no reporting at all).
  Progress* get() { return caller_ ? this : nullptr; }

  /// The job's next stage named `name` starts; planned stages before it that did not run are
  /// credited as done. A name not in the plan (a bug) is announced without moving on.
  void begin_stage(std::string_view name) {
    if (!caller_) return;
    std::lock_guard lock(mutex_);
    std::size_t at = next_;
    while (at < plan_.size() && plan_[at].name != name) ++at;
    if (at == plan_.size()) {
      caller_->begin(StageInfo{name, static_cast<int>(next_), static_cast<int>(plan_.size())});
      return;
    }
    if (current_ < plan_.size()) done_ += plan_[current_].weight;  // the stage that ended
    for (; next_ < at; ++next_) done_ += plan_[next_].weight;      // planned, not needed
    current_ = next_++;
    caller_->begin(StageInfo{name, static_cast<int>(current_ + 1), static_cast<int>(plan_.size())});
    forward(0);
  }

  /// The job ended: overall 1.
  void finish() {
    if (!caller_) return;
    std::lock_guard lock(mutex_);
    done_ = total_;
    current_ = plan_.size();
    shown_ = 1;
    caller_->report(1, 1);
  }

  void begin(std::string_view) override {}  // stages' own announcements: the plan's stand
  bool report(double fraction) override {
    std::lock_guard lock(mutex_);
    return forward(std::clamp(fraction, 0.0, 1.0));
  }

 private:
  bool forward(double fraction) {
    const double w = current_ < plan_.size() ? plan_[current_].weight : 0;
    shown_ = std::max(shown_, std::min(1.0, (done_ + w * fraction) / std::max(total_, 1e-300)));
    // The current stage's share is credited when the next stage begins.
    if (fraction >= 1 && current_ < plan_.size()) done_ += w, current_ = plan_.size();
    return caller_->report(fraction, shown_);
  }

  Progress* caller_;
  std::vector<PlannedStage> plan_;
  double total_ = 0, done_ = 0, shown_ = 0;
  std::size_t next_ = 0, current_ = static_cast<std::size_t>(-1);
  std::mutex mutex_;
};

}  // namespace tpmsfill::detail
