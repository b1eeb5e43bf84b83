/// @file BenchTiming.h
/// Repeat-and-median runner shared by every suite.
#pragma once

#include <chrono>
#include <functional>
#include <vector>

namespace tg::bench {

/// Summary of repeated measurements of one case.
struct TimingSummary {
  double medianMs = 0.0;
  double minMs = 0.0;
  double maxMs = 0.0;
  int reps = 0;
};

/// Median (mean of the two middle values for an even count), minimum and maximum of `samples`.
TimingSummary summarize(std::vector<double> samples);

/// Calls `sample(k)` once for k = 0 as an untimed warm-up (first-touch page faults, lazily
/// started worker threads and caches would otherwise land in the first sample), then for
/// k = 1..reps, and summarises what those calls returned. Each call returns the milliseconds
/// it measured itself, so that per-repetition setup (moving instances, resetting buffers) stays
/// outside the measurement.
TimingSummary measureRepeated(int reps, const std::function<double(int)>& sample);

/// measureRepeated for several cases at once, interleaved: `reps` rounds in which every case
/// is sampled twice in a row, the first call untimed, the second timed. The machines these
/// figures come from change speed by up to a quarter within minutes; timed in rounds, every
/// case sees the same machine states, and ratios between cases are far steadier than between
/// cases timed one after the other. The untimed call before each timed one gives the case back
/// its own warm caches (and a task arena its awake workers), which the other cases' calls took
/// away: timed right after another case, a trace of the BART kitchen ran up to 15% slower.
/// Returns one summary per case.
std::vector<TimingSummary> measureInterleaved(
    int reps, const std::vector<std::function<double(int)>>& samples);

/// Wall-clock milliseconds taken by `f()`.
template <typename F>
double timeMs(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace tg::bench
