#include "BenchTiming.h"

#include <algorithm>
#include <stdexcept>

namespace tg::bench {

TimingSummary summarize(std::vector<double> samples) {
  TimingSummary s;
  s.reps = static_cast<int>(samples.size());
  if (samples.empty()) return s;
  std::sort(samples.begin(), samples.end());
  const std::size_t n = samples.size();
  s.medianMs = n % 2 == 1 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
  s.minMs = samples.front();
  s.maxMs = samples.back();
  return s;
}

TimingSummary measureRepeated(int reps, const std::function<double(int)>& sample) {
  if (reps < 1) throw std::invalid_argument("measureRepeated: reps must be at least 1");
  sample(0);
  std::vector<double> samples;
  samples.reserve(static_cast<std::size_t>(reps));
  for (int k = 1; k <= reps; ++k) samples.push_back(sample(k));
  return summarize(std::move(samples));
}

std::vector<TimingSummary> measureInterleaved(
    int reps, const std::vector<std::function<double(int)>>& samples) {
  if (reps < 1) throw std::invalid_argument("measureInterleaved: reps must be at least 1");
  std::vector<std::vector<double>> times(samples.size());
  for (auto& t : times) t.reserve(static_cast<std::size_t>(reps));
  for (int k = 1; k <= reps; ++k)
    for (std::size_t i = 0; i < samples.size(); ++i) {
      samples[i](0);
      times[i].push_back(samples[i](k));
    }
  std::vector<TimingSummary> out;
  out.reserve(samples.size());
  for (auto& t : times) out.push_back(summarize(std::move(t)));
  return out;
}

}  // namespace tg::bench
