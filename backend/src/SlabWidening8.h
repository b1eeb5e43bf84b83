// The slab test's interval widening for eight boxes or lanes in one 256-bit register, shared
// by the AVX2 packet kernel and the eight-wide single-ray walk. Internal header: not installed.
//
// Internal linkage and always inlined: the helper is compiled for AVX2 wherever it is used (see
// PacketKernel.h for why no out-of-line copy may be shared with baseline code).
#pragma once

#include <immintrin.h>

#include "Bvh4.h"

namespace tg::detail {
namespace {

/// Widens [tmin, tmax] by kBvhIntervalSlack of each end's magnitude, as intersectBvh4Node
/// does four boxes at a time (see there): one product per end when every lane's tnear is >= 0.
[[gnu::always_inline, gnu::target("avx2")]] inline void widenSlabInterval8(__m256& tmin,
                                                                           __m256& tmax,
                                                                           bool nonNegativeTnear) {
  if (nonNegativeTnear) {
    // The factors from memory (see kBvhWidenFactors): operands of the products, not broadcasts
    // made again at every node.
    tmin = _mm256_mul_ps(tmin, _mm256_load_ps(kBvhWidenFactors[0]));
    tmax = _mm256_mul_ps(tmax, _mm256_load_ps(kBvhWidenFactors[1]));
  } else {
    const __m256 absMask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
    const __m256 slack = _mm256_set1_ps(kBvhIntervalSlack);
    tmin = _mm256_sub_ps(tmin, _mm256_mul_ps(_mm256_and_ps(tmin, absMask), slack));
    tmax = _mm256_add_ps(tmax, _mm256_mul_ps(_mm256_and_ps(tmax, absMask), slack));
  }
}

}  // namespace
}  // namespace tg::detail
