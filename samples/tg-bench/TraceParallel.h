/// @file TraceParallel.h
/// The one parallel loop every trace implementation runs its rays through, so that
/// Tracegraph and the peer differ only in the per-ray call.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>

namespace tg::bench {

/// Rays per task: large enough to amortise scheduling, small enough (a quarter of a 1024-pixel
/// row) to balance image regions of very different cost.
inline constexpr std::size_t kRaysPerTask = 256;

/// Calls body(begin, end) over [0, count) in parallel in the calling task arena.
template <typename Body>
void parallelOverRays(std::size_t count, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kRaysPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace tg::bench
