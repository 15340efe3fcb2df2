/// @file job_progress.hpp
/// @brief A job's plan of stages over the caller's Progress: numbered stages, one begin per
/// stage that runs whatever the stage functions announce inside it, fractions that never go
/// back, at most kMaxReportsPerStage reports per stage, and the overall fraction.
///
/// Use: make a JobProgress from the caller's Progress and the plan; pass get() to the stage
/// functions as their Progress; around each stage call begin_stage(name) and end_stage()
/// (the field job's StageClock does both); finish() when the job is done. The stage functions' own
/// begin() calls arrive here and are forwarded as parts (StageInfo::step) of the planned stage,
/// or dropped when they repeat its name; their report() calls are forwarded with the overall.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "tpmsfill/error.hpp"
#include "tpmsfill/progress.hpp"

namespace tpmsfill::detail {

/// One planned stage and its rough share of the job's time (any positive unit).
struct PlannedStage {
  std::string name;
  double weight = 1;
};

class JobProgress final : public Progress {
 public:
  JobProgress(Progress* caller, std::vector<PlannedStage> plan)
      : caller_(caller), plan_(std::move(plan)) {
    for (const PlannedStage& s : plan_) total_ += s.weight;
  }

  /// What the stage functions report to: this object when there is a caller, else null (no
  /// reporting at all, and no locking).
  Progress* get() { return caller_ ? this : nullptr; }

  /// The plan's next stage named `name` starts (from the job's thread). Planned stages before
  /// it that did not run are credited as done. A name the rest of the plan does not hold (a
  /// bug in the plan) is announced as a part of the current stage, so the numbering stays.
  /// @throws Cancelled  the caller's report at the stage's start said stop
  void begin_stage(std::string_view name) {
    if (!caller_) return;
    std::lock_guard lock(mutex_);
    if (cancelled_) throw Cancelled("cancelled");
    std::size_t at = next_;
    while (at < plan_.size() && plan_[at].name != name) ++at;
    if (at == plan_.size()) return announce_part(name);
    close_current();
    for (; next_ < at; ++next_) done_ += plan_[next_].weight;  // planned, not needed
    current_ = at;
    next_ = at + 1;
    fraction_ = 0;
    percent_ = -1;
    caller_->begin(
        StageInfo{plan_[at].name, static_cast<int>(at + 1), static_cast<int>(plan_.size())});
    if (!forward(0)) throw Cancelled("cancelled");
  }

  /// The current stage ended (from the job's thread): its fraction 1, if it did not say so.
  /// @throws Cancelled  the caller's report said stop
  void end_stage() {
    if (!caller_) return;
    std::lock_guard lock(mutex_);
    if (cancelled_ || (current_ != kNone && !forward(1))) throw Cancelled("cancelled");
    close_current();
  }

  /// The job is done: every planned stage credited, the overall 1 (reported unless it was).
  void finish() {
    if (!caller_) return;
    std::lock_guard lock(mutex_);
    close_current();
    done_ = total_;
    next_ = plan_.size();
    if (overall_ < 1 && !cancelled_) caller_->report(1, overall_ = 1);
  }

  /// A stage function inside the current stage announces itself: a part of the stage, unless
  /// it repeats the stage's name.
  void begin(std::string_view name) override {
    std::lock_guard lock(mutex_);
    if (cancelled_ || (current_ != kNone && plan_[current_].name == name)) return;
    announce_part(name);
  }

  bool report(double fraction) override {
    std::lock_guard lock(mutex_);
    if (cancelled_) return false;
    if (current_ == kNone) return true;  // between stages: nothing to attribute it to
    return forward(fraction);
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  void announce_part(std::string_view part) {
    const std::size_t at = current_ != kNone ? current_ : next_ ? next_ - 1 : kNone;
    if (at == kNone) return;  // before the first stage: nothing to attach it to
    caller_->begin(
        StageInfo{plan_[at].name, static_cast<int>(at + 1), static_cast<int>(plan_.size()), part});
  }

  // The current stage's share counts as done.
  void close_current() {
    if (current_ == kNone) return;
    done_ += plan_[current_].weight;
    current_ = kNone;
  }

  // Forwards the current stage's fraction once its whole percent moves on; the stage fraction
  // and the overall only ever grow. Returns the caller's word (true when nothing was sent).
  bool forward(double fraction) {
    fraction_ = std::max(fraction_, std::clamp(fraction, 0.0, 1.0));
    const int percent = static_cast<int>(std::floor(100 * fraction_));
    if (percent <= percent_) return true;
    percent_ = percent;
    // The last planned stage's end is the job's end: exactly 1, whatever the rounding.
    const bool last = current_ + 1 == plan_.size() && fraction_ == 1;
    const double at = (done_ + plan_[current_].weight * fraction_) / std::max(total_, 1e-300);
    overall_ = last ? 1.0 : std::max(overall_, std::min(at, 1.0));
    if (!caller_->report(fraction_, overall_)) cancelled_ = true;
    return !cancelled_;
  }

  Progress* caller_;
  std::vector<PlannedStage> plan_;
  double total_ = 0;
  double done_ = 0;      ///< weight of the stages ended or skipped
  double fraction_ = 0;  ///< the current stage's fraction, the largest reported
  double overall_ = 0;   ///< the last overall reported
  int percent_ = -1;     ///< the current stage's whole percent last reported
  std::size_t current_ = kNone, next_ = 0;
  bool cancelled_ = false;
  std::mutex mutex_;
};

}  // namespace tpmsfill::detail
