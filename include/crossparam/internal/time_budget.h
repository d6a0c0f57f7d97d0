// SPDX-License-Identifier: GPL-3.0-or-later
// The time budget of one computation (named parameters `time_limit` and `best_effort`): a deadline on the
// steady clock, checked between steps and inside long loops.
#ifndef CROSSPARAM_INTERNAL_TIME_BUDGET_H
#define CROSSPARAM_INTERNAL_TIME_BUDGET_H

#include <crossparam/errors.h>
#include <crossparam/parameters.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <string>

namespace crossparam {
namespace internal {

/// A deadline, or none. `stop()` is the one check: false while time is left; once it has run out, true with
/// best effort (the caller ends its improving loop and keeps its valid state), else Time_limit_error.
class Time_budget {
public:
  using clock = std::chrono::steady_clock;

  /// No limit.
  Time_budget() = default;

  /// `seconds` from now; `best_effort` as the named parameter.
  /// A limit that is not a finite non-negative number is no limit (the entry points reject such values).
  Time_budget(double seconds, bool best_effort) : seconds_(seconds), best_effort_(best_effort) {
    limited_ = std::isfinite(seconds) && seconds >= 0;
    if (limited_)
      deadline_ = clock::now() + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(seconds));
  }

  /// The budget of the named parameters `time_limit` and `best_effort` in `np`, from now.
  /// \throws Input_error if the time limit is not a non-negative number.
  template <class NP>
  static Time_budget from(const NP& np) {
    using CGAL::parameters::choose_parameter;
    using CGAL::parameters::get_parameter;
    const double seconds = choose_parameter(get_parameter(np, internal_np::time_limit_t()), HUGE_VAL);
    if (!(seconds >= 0)) throw Input_error("the time limit must be a non-negative number of seconds");
    return Time_budget(seconds, choose_parameter(get_parameter(np, internal_np::best_effort_t()), false));
  }

  bool limited() const { return limited_; }
  bool best_effort() const { return best_effort_; }
  /// The budget's length in seconds (infinite without a limit).
  double seconds() const { return limited_ ? seconds_ : HUGE_VAL; }
  /// Seconds left (infinite without a limit, 0 once run out): the budget of a nested computation.
  double remaining() const {
    if (!limited_) return HUGE_VAL;
    const double left = std::chrono::duration<double>(deadline_ - clock::now()).count();
    return left > 0 ? left : 0;
  }
  bool expired() const { return limited_ && clock::now() >= deadline_; }

  /// Inside an improving loop of `stage`: false while time is left; once it has run out, true with best effort,
  /// else throws Time_limit_error(stage, reached()).
  bool stop(const std::string& stage, const std::function<std::string()>& reached) const {
    if (!expired()) return false;
    if (best_effort_) return true;
    throw Time_limit_error(stage, reached ? reached() : std::string(), seconds_);
  }

  /// Between or inside steps that must finish: throws Time_limit_error(stage, reached()) once time has run out,
  /// whatever best effort says.
  void check(const std::string& stage, const std::function<std::string()>& reached = {}) const {
    if (expired()) throw Time_limit_error(stage, reached ? reached() : std::string(), seconds_);
  }

private:
  double seconds_ = HUGE_VAL;
  bool limited_ = false;
  bool best_effort_ = false;
  clock::time_point deadline_{};
};

} // namespace internal
} // namespace crossparam

#endif // CROSSPARAM_INTERNAL_TIME_BUDGET_H
