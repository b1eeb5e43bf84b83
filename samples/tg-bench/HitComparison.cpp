#include "HitComparison.h"

#include <algorithm>

namespace tg::bench {

MismatchCounts compareOutcomes(std::span<const RayOutcome> a, std::span<const RayOutcome> b) {
  MismatchCounts counts;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i].hit() != b[i].hit()) {
      ++counts.hitMiss;
    } else if (a[i].hit() && (a[i].instance != b[i].instance || a[i].prim != b[i].prim)) {
      ++counts.prim;
    }
  }
  return counts;
}

MismatchCounts compareOcclusion(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  MismatchCounts counts;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i)
    if ((a[i] != 0) != (b[i] != 0)) ++counts.hitMiss;
  return counts;
}

}  // namespace tg::bench
