// A packet's lanes against one box, eight lanes per AVX instruction: the test a packet from
// outside the top level's box takes before its walk (TopLevelBvh). Include only from translation
// units compiled with AVX2. Internal header: not installed.
#pragma once

#include <immintrin.h>

#include "PacketKernel.h"
#include "SlabWidening8.h"

namespace tg::detail {
namespace {

/// The lanes of `lanes` whose rays meet the box in slot 0 of `node` within [tnear, tfar], with
/// the walks' box arithmetic (intersectBvh4Node, lane by lane) and the widening of either tnear
/// sign (a PacketOneBoxFn).
unsigned meetsOneBoxAvx(const Bvh4Node& node, const PacketBoxRays& rays, unsigned lanes) {
  __m256 tmin = _mm256_load_ps(rays.tnear), tmax = _mm256_load_ps(rays.tfar);
  for (int a = 0; a < 3; ++a) {
    const int negative = static_cast<int>((rays.signs >> a) & 1u);
    const __m256 origin = _mm256_load_ps(rays.origin[a]);
    const __m256 reciprocal = _mm256_load_ps(rays.reciprocal[a]);
    const __m256 n = _mm256_mul_ps(
        _mm256_sub_ps(_mm256_set1_ps(node.bounds[2 * a + negative][0]), origin), reciprocal);
    const __m256 f = _mm256_mul_ps(
        _mm256_sub_ps(_mm256_set1_ps(node.bounds[2 * a + 1 - negative][0]), origin), reciprocal);
    // MAXPS/MINPS keep the second operand for a NaN slab distance, as the walks do.
    tmin = _mm256_max_ps(n, tmin);
    tmax = _mm256_min_ps(f, tmax);
  }
  widenSlabInterval8(tmin, tmax, false);
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OS))) & lanes;
}

}  // namespace
}  // namespace tg::detail
