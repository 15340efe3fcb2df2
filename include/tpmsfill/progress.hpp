/// @file progress.hpp
/// @brief Progress and cancellation through one small interface (as OpenVDB's interrupter).
///
/// A job runs stages one after another. Every stage fill() runs is announced by begin(), then
/// report() gives the fraction of that stage done; report() returning false cancels the job
/// (the stage throws tpmsfill::Cancelled, and nothing is returned or written). Callers that
/// want the whole job's position override the richer pair: begin(const StageInfo&) says which
/// stage of how many begins, report(stage_fraction, overall) adds the job's overall fraction.
/// By default each forwards to the simple one, so overriding either pair is enough.
///
/// The contract, for fill():
///  - Stages: every stage in the report's stage table is announced once, in order, with
///    index 1..count; count is the job's plan, fixed when it starts (an auto inside rule plans
///    the clean and second classification it may need; when they are not needed they are
///    skipped, never announced, and their share is credited).
///  - Fractions: a stage's fraction is in [0, 1]; the overall fraction never decreases, stays
///    in [0, 1] and is exactly 1 when the job's last stage ends. A stage is reported at most a
///    few hundred times.
///  - Threads: begin() comes from the thread that called fill(). report() may come from any
///    worker thread, but never from two at once (calls are serialised), so an implementation
///    needs no lock of its own for calls from one job. Keep both cheap: they run inside the
///    job's parallel loops.
///  - Cancelling: report() returning false makes the job throw Cancelled from fill()'s thread
///    at the next check, within a fraction of a stage.
/// A null Progress pointer in an options struct means "no reporting".
#pragma once

#include <string_view>

namespace tpmsfill {

/// A stage of a planned job: its name, and its place in the plan (1-based; count stages).
struct StageInfo {
  std::string_view name;
  int index = 0;
  int count = 0;
};

class Progress {
 public:
  virtual ~Progress() = default;
  /// A stage starts (a short lowercase name such as "classify" or "distance").
  virtual void begin(std::string_view stage) { (void)stage; }
  /// Fraction of the current stage done, in [0, 1]. Return false to cancel the job.
  virtual bool report(double fraction) {
    (void)fraction;
    return true;
  }
  /// A stage of a planned job starts (default: begin(stage.name)).
  virtual void begin(const StageInfo& stage) { begin(stage.name); }
  /// Fraction of the current stage and of the whole job done (default: report(stage)).
  virtual bool report(double stage, double overall) {
    (void)overall;
    return report(stage);
  }
};

}  // namespace tpmsfill
