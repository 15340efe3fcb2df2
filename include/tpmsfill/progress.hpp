/// @file progress.hpp
/// @brief Progress and cancellation through one small interface (as OpenVDB's interrupter).
///
/// Long stages call begin() once and then report() between chunks of work; report() returning
/// false cancels the job (the stage throws tpmsfill::Cancelled). Calls may come from any
/// thread, so implementations must be thread-safe; report() is called at most a few hundred
/// times per stage. A null Progress pointer in an options struct means "no reporting".
#pragma once

#include <string_view>

namespace tpmsfill {

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
};

}  // namespace tpmsfill
