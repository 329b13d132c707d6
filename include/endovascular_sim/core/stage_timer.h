// One clock for the consecutive stages of a step: every stage is charged
// the time from the mark before it to the mark after it, and the time
// between named stages goes to one remainder, so that a step's stage times
// and its remainder add up to its wall time (StepStats).
#pragma once

#include <chrono>

namespace evsim {

class StageTimer {
 public:
  using Clock = std::chrono::steady_clock;

  /// Starts the clock; the time between stages is added to *rest_ms [ms]
  /// (nullptr: not kept).
  explicit StageTimer(double* rest_ms = nullptr) : rest_ms_(rest_ms), start_(Clock::now()) {
    mark_ = start_;
  }

  /// A stage begins: the time since the last mark goes to the remainder.
  void begin() { charge(rest_ms_); }

  /// The stage begun last ends: the time since the last mark is added to
  /// *stage_ms [ms] (nullptr: to the remainder).
  void end(double* stage_ms) { charge(stage_ms ? stage_ms : rest_ms_); }

  /// From the start to the last mark [ms]: the sum of everything charged.
  double elapsedMs() const {
    return std::chrono::duration<double, std::milli>(mark_ - start_).count();
  }

 private:
  void charge(double* ms) {
    const Clock::time_point now = Clock::now();
    if (ms) *ms += std::chrono::duration<double, std::milli>(now - mark_).count();
    mark_ = now;
  }

  double* rest_ms_;
  Clock::time_point start_, mark_;
};

}  // namespace evsim
