// The object rows of a packet entering an instance, for the AVX2 and AVX-512 kernels. Include
// only from translation units compiled with AVX2 and without contraction, after
// PacketLanesAvx.h. PacketShear's permutation rules are written again here (PermutationBits)
// rather than called: its inline functions are baseline code, which a kernel must not compile
// into a copy of its own (see PacketKernel.h). Internal header: not installed.
#pragma once

#include <immintrin.h>

#include "PacketLanesAvx.h"

namespace tg::detail {
namespace {

/// The four lanes of `v` from `half` (0: lanes 0-3, 1: lanes 4-7) widened to double, exactly.
[[gnu::always_inline]] inline __m256d widenHalf(__m256 v, int half) {
  return _mm256_cvtps_pd(half == 0 ? _mm256_castps256_ps128(v) : _mm256_extractf128_ps(v, 1));
}

/// Rounds two rows of four doubles (lanes 0-3, 4-7) to one row of eight floats, each as
/// static_cast<float> does.
[[gnu::always_inline]] inline __m256 narrowHalves(__m256d lo, __m256d hi) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(lo)), _mm256_cvtpd_ps(hi), 1);
}

/// Writes lane `lead`'s value into every lane of the eight doubles at `values` outside the
/// lanes `keep`, without a branch per lane (which lanes keep their own varies from packet to
/// packet).
[[gnu::always_inline]] inline void spreadLane(double* values, unsigned keep, unsigned lead) {
  const __m256d value = _mm256_broadcast_sd(values + lead);
  const __m256i bits = _mm256_setr_epi64x(1, 2, 4, 8);
  for (unsigned h = 0; h < 2; ++h) {
    const __m256i word = _mm256_set1_epi64x(static_cast<long long>(keep >> (4 * h)));
    const __m256d own = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(word, bits), bits));
    double* half = values + 4 * h;
    _mm256_storeu_pd(half, _mm256_blendv_pd(value, _mm256_loadu_pd(half), own));
  }
}

/// The axis permutations of eight directions, as PacketShear's bits.
struct PermutationBits {
  unsigned zIsX, zIsY, swapped;
  /// The lanes of `lanes` whose permutation is lane `lead`'s (PacketShear::samePermutation).
  unsigned same(unsigned lanes, unsigned lead) const {
    const auto sameAs = [&](unsigned bits) { return (bits >> lead) & 1u ? bits : ~bits; };
    return lanes & sameAs(zIsX) & sameAs(zIsY) & sameAs(swapped);
  }
  /// What a row load found: `coherent`, its lanes with lane `lead`'s permutation, and that
  /// permutation.
  LoadedLanes loaded(unsigned coherent, unsigned lead) const {
    const int kz = (zIsX >> lead) & 1u ? 0 : ((zIsY >> lead) & 1u ? 1 : 2);
    return {coherent, same(coherent, lead), kz, ((swapped >> lead) & 1u) != 0};
  }
};

/// shearPacket on the direction rows d (float, eight lanes): kz the first largest |component|,
/// kx and ky swapped when dir[kz] < 0; writes tri.sx and tri.sy and returns the permutations.
[[gnu::always_inline]] inline PermutationBits shearRows(const __m256 (&d)[3],
                                                        PacketTriangleRays& tri) {
  const __m256 absMask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  const __m256 ax = _mm256_and_ps(d[0], absMask), ay = _mm256_and_ps(d[1], absMask),
               az = _mm256_and_ps(d[2], absMask);
  const __m256 xGeY = _mm256_cmp_ps(ax, ay, _CMP_GE_OQ);
  const __m256 zIsX = _mm256_and_ps(xGeY, _mm256_cmp_ps(ax, az, _CMP_GE_OQ));
  const __m256 zIsY = _mm256_andnot_ps(xGeY, _mm256_cmp_ps(ay, az, _CMP_GE_OQ));
  // select(c, a, b) = c ? a : b, as shearPacket's.
  const auto select = [](__m256 c, __m256 a, __m256 b) { return _mm256_blendv_ps(b, a, c); };
  const __m256 dkz = select(zIsX, d[0], select(zIsY, d[1], d[2]));
  const __m256 dkx = select(zIsX, d[1], select(zIsY, d[2], d[0]));
  const __m256 dky = select(zIsX, d[2], select(zIsY, d[0], d[1]));
  const __m256 swap = _mm256_cmp_ps(dkz, _mm256_setzero_ps(), _CMP_LT_OQ);
  _mm256_store_ps(tri.sx, _mm256_div_ps(select(swap, dky, dkx), dkz));
  _mm256_store_ps(tri.sy, _mm256_div_ps(select(swap, dkx, dky), dkz));
  return {static_cast<unsigned>(_mm256_movemask_ps(zIsX)),
          static_cast<unsigned>(_mm256_movemask_ps(zIsY)),
          static_cast<unsigned>(_mm256_movemask_ps(swap))};
}

/// Gives every lane of `tri`'s rows outside `filtered` lane `lead`'s numbers.
[[gnu::always_inline]] inline void spreadTriangleRows(PacketTriangleRays& tri, unsigned filtered,
                                                      unsigned lead) {
  if (filtered == kAllLanes) return;
  const __m256 keep = Avx8LaneOps::laneMask(filtered);
  const __m256i leadIndex = _mm256_set1_epi32(static_cast<int>(lead));
  for (int a = 0; a < 3; ++a) {
    spreadLane(tri.origin[a], keep, leadIndex);
    spreadLane(tri.originD[a], filtered, lead);
    spreadLane(tri.directionD[a], filtered, lead);
  }
  spreadLane(tri.sx, keep, leadIndex);
  spreadLane(tri.sy, keep, leadIndex);
  spreadLane(tri.tnear, keep, leadIndex);
}

/// The TransformedRowsFn of the AVX kernels: loadTransformedRows (PacketTransformedRays.h) eight
/// float lanes or four double lanes per instruction, with the same products, sums, roundings,
/// comparisons and divisions in the same order, so the same bits. Callgrind, primary packets
/// from the robots' camera: about 320 instructions per call against the portable version's
/// 1,230 (its lane loops: the sign and permutation tests, the reciprocals' zero rule, the lanes
/// that copy the first).
LoadedLanes loadTransformedRowsAvx(const Ray* rays, const Affine3d& worldToObject, unsigned lanes,
                                   const float* tfar, PacketBoxRays& box, PacketTriangleRays& tri) {
  __m256 world[8];
  transposeRays(rays, world);
  const double(&m)[3][4] = worldToObject.m;

  // mapPacketRows: per half, o = ((m0 ox + m1 oy) + m2 oz) + m3 and d = (m0 dx + m1 dy) + m2 dz,
  // Affine3::transformPoint's and transformVector's order.
  __m256 origin[3], direction[3];
  for (int r = 0; r < 3; ++r) {
    const __m256d m0 = _mm256_set1_pd(m[r][0]), m1 = _mm256_set1_pd(m[r][1]),
                  m2 = _mm256_set1_pd(m[r][2]), m3 = _mm256_set1_pd(m[r][3]);
    __m256d o[2], d[2];
    for (int h = 0; h < 2; ++h) {
      o[h] = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m0, widenHalf(world[0], h)),
                                                       _mm256_mul_pd(m1, widenHalf(world[1], h))),
                                         _mm256_mul_pd(m2, widenHalf(world[2], h))),
                           m3);
      d[h] = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m0, widenHalf(world[4], h)),
                                         _mm256_mul_pd(m1, widenHalf(world[5], h))),
                           _mm256_mul_pd(m2, widenHalf(world[6], h)));
      _mm256_storeu_pd(tri.originD[r] + 4 * h, o[h]);
      _mm256_storeu_pd(tri.directionD[r] + 4 * h, d[h]);
    }
    origin[r] = narrowHalves(o[0], o[1]);
    direction[r] = narrowHalves(d[0], d[1]);
  }
  const PermutationBits permutations = shearRows(direction, tri);

  // Box rows: the lanes whose direction signs match the first lane's.
  const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 inf = _mm256_set1_ps(__builtin_inff());
  const unsigned first = static_cast<unsigned>(__builtin_ctz(lanes));
  unsigned coherent = lanes, signs = 0;
  for (int a = 0; a < 3; ++a) {
    const auto negative =
        static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(direction[a], zero, _CMP_LT_OQ)));
    const bool lead = (negative >> first) & 1u;
    coherent &= lead ? negative : ~negative;
    signs |= (lead ? 1u : 0u) << a;
    _mm256_store_ps(box.origin[a], origin[a]);
    _mm256_store_ps(tri.origin[a], origin[a]);
    // Bvh4Ray's reciprocal: +inf for a zero component whatever its sign.
    _mm256_store_ps(box.reciprocal[a],
                    _mm256_blendv_ps(_mm256_div_ps(one, direction[a]), inf,
                                     _mm256_cmp_ps(direction[a], zero, _CMP_EQ_OQ)));
  }
  _mm256_store_ps(box.tnear, world[3]);
  _mm256_store_ps(tri.tnear, world[3]);
  // tfar is read in `lanes` only; the other lanes are not coherent and take the first's below.
  _mm256_store_ps(box.tfar,
                  _mm256_maskload_ps(tfar, _mm256_castps_si256(Avx8LaneOps::laneMask(lanes))));
  box.signs = signs;
  spreadBoxRows(box, coherent, first);

  // Triangle rows: the coherent lanes with the first lane's axis permutation.
  const LoadedLanes found = permutations.loaded(coherent, first);
  spreadTriangleRows(tri, found.filtered, first);
  return found;
}

/// The IdentityRowsFn of the AVX kernels: loadIdentityRows (PacketObjectRays.h) eight lanes per
/// instruction (the doubles are the floats widened, four per instruction), with the same
/// comparisons and divisions, so the same bits; the reciprocals, which the walk has in its box
/// rows already, are not divided again.
LoadedLanes loadIdentityRowsAvx(const Ray* rays, unsigned lanes, PacketTriangleRays& tri) {
  __m256 row[8];
  transposeRays(rays, row);
  const __m256 direction[3] = {row[4], row[5], row[6]};
  const PermutationBits permutations = shearRows(direction, tri);
  for (int a = 0; a < 3; ++a) {
    _mm256_store_ps(tri.origin[a], row[a]);
    for (int h = 0; h < 2; ++h) {
      _mm256_storeu_pd(tri.originD[a] + 4 * h, widenHalf(row[a], h));
      _mm256_storeu_pd(tri.directionD[a] + 4 * h, widenHalf(row[4 + a], h));
    }
  }
  _mm256_store_ps(tri.tnear, row[3]);
  const unsigned first = static_cast<unsigned>(__builtin_ctz(lanes));
  const LoadedLanes found = permutations.loaded(lanes, first);
  spreadTriangleRows(tri, found.filtered, first);
  return found;
}

}  // namespace
}  // namespace tg::detail
