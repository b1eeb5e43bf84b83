/// @file Clock.h
/// Scene time, advanced by the application and read by animators.
#pragma once

#include <cstdint>

namespace tg {

/// Scene time in seconds. The application advances it (from wall time for interactive use,
/// in fixed steps for offline frames); animators are evaluated at its value.
class Clock {
 public:
  /// Current time in seconds.
  double time() const { return time_; }
  /// Number of times the clock was set since creation.
  std::uint64_t ticks() const { return ticks_; }
  /// Sets the time (it may go backwards: scrubbing).
  void setTime(double seconds) {
    time_ = seconds;
    ++ticks_;
  }
  /// Advances by `seconds`.
  void advance(double seconds) { setTime(time_ + seconds); }

 private:
  double time_ = 0.0;
  std::uint64_t ticks_ = 0;
};

}  // namespace tg
