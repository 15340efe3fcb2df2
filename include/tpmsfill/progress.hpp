/// @file progress.hpp
/// @brief Progress and cancellation through one small interface (as OpenVDB's interrupter).
///
/// A job runs stages one after another. Each stage is announced by begin(), then report()
/// gives the fraction of that stage done; report() returning false cancels the job. There are
/// two pairs of virtual functions. The simple pair, begin(name) and report(fraction), is what a
/// single stage function (classify_grid, band_distances, ...) calls. The richer pair,
/// begin(const StageInfo&) and report(stage, overall), is what a planned job (fill()) calls: it
/// adds the stage's place in the job and the job's overall fraction. By default the richer
/// pair forwards to the simple one, so a Progress overrides whichever pair it wants.
///
/// The contract, for fill() (the same for any job that plans its stages):
///  - Plan: the job fixes its plan of stages when it starts; `count` is that plan's length and
///    never changes. Stages the job finds it does not need (an auto inside rule plans the clean
///    and the second classification it may need) are skipped: never announced, their share of
///    the overall fraction credited as done, so the overall never goes back.
///  - Stages: every stage the job runs is announced once by begin(StageInfo) with an empty
///    `step`, in the order of the report's stage table, with `index` (1-based) strictly
///    increasing and at most `count`. A stage's own parts (another stage function it calls
///    whose name differs) are announced by begin(StageInfo) with the same name, index and
///    count and the part's name in `step`; the default begin(StageInfo) ignores those.
///  - Fractions: within a stage the fraction starts at 0 (reported at begin), never
///    decreases, and ends at 1 (reported when the stage ends); the overall fraction stays in
///    [0, 1], never decreases, and is exactly 1 on the job's last report. report() is called
///    at most kMaxReportsPerStage times per stage: once per whole percent the stage moves on.
///  - Threads: begin() is called from the thread that called the job. report() may be called
///    from any of the job's worker threads, but calls for one job are serialised (never two at
///    once, and never during a begin()), so a Progress used by one job needs no lock. Both run
///    inside the job's loops and under its lock: keep them cheap, and do not throw from them.
///  - Cancelling: once report() returns false, the job stops calling the Progress and throws
///    tpmsfill::Cancelled from the thread that called it, at its next check: within about a
///    percent of a stage that reports fractions (measure: between its five phases), at the
///    start or end of one that does not (review, spatial, clean, depth, band and islands report
///    only those). Nothing is returned and nothing is written.
/// A null Progress pointer in an options struct means "no reporting".
/// The single stage functions keep the simple contract: begin(name) once, then fractions of
/// that stage (from worker threads, serialised by the caller's Progress if it needs it).
#pragma once

#include <string_view>

namespace tpmsfill {

/// report() calls per stage of a planned job, at most: its start, each whole percent, its end.
inline constexpr int kMaxReportsPerStage = 101;

/// A stage of a planned job: its name and its place in the plan (1-based, of count), or one of
/// its parts (step: the name a stage function called inside it announced).
struct StageInfo {
  std::string_view name;
  int index = 0;
  int count = 0;
  std::string_view step{};  ///< empty when the stage itself begins
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
  /// A stage of a planned job starts, or a part of it (default: begin(stage.name) for a
  /// stage, nothing for a part).
  virtual void begin(const StageInfo& stage) {
    if (stage.step.empty()) begin(stage.name);
  }
  /// Fraction of the current stage and of the whole job done (default: report(stage)).
  /// Return false to cancel the job.
  virtual bool report(double stage, double overall) {
    (void)overall;
    return report(stage);
  }
};

}  // namespace tpmsfill
