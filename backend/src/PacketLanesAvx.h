// Eight lanes in an AVX register, for the triangle test of the AVX2 and AVX-512 kernels (see
// PacketTriangleTest.h). Include only from translation units compiled with AVX2.
// Internal header: not installed.
#pragma once

#include <immintrin.h>

#include "PacketTriangleTest.h"

namespace tg::detail {
namespace {

/// The packet walk's lane operations (see ScalarLaneOps in PacketTraversalImpl.h) on one
/// 8-lane register: same answers, no loop over the lanes.
struct Avx8LaneOps {
  /// `mask` as a register: all bits set in the lanes it holds.
  static __m256 laneMask(unsigned mask) {
    const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(
        _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(mask)), bits), bits));
  }
  /// The lanes l of `mask` whose entry[l] lies beyond tfar[l] (ordered compare: false for NaN).
  static unsigned beyond(const float* entry, const float* tfar, unsigned mask) {
    const __m256 gt = _mm256_cmp_ps(_mm256_loadu_ps(entry), _mm256_loadu_ps(tfar), _CMP_GT_OQ);
    return static_cast<unsigned>(_mm256_movemask_ps(gt)) & mask;
  }
};

/// Eight doubles in two AVX registers (lanes 0-3, 4-7).
struct Doubles8 {
  __m256d lo, hi;
  static Doubles8 load(const double* p) { return {_mm256_load_pd(p), _mm256_load_pd(p + 4)}; }
  static Doubles8 broadcast(double x) { return {_mm256_set1_pd(x), _mm256_set1_pd(x)}; }
  friend Doubles8 operator+(Doubles8 a, Doubles8 b) {
    return {_mm256_add_pd(a.lo, b.lo), _mm256_add_pd(a.hi, b.hi)};
  }
  friend Doubles8 operator-(Doubles8 a, Doubles8 b) {
    return {_mm256_sub_pd(a.lo, b.lo), _mm256_sub_pd(a.hi, b.hi)};
  }
  friend Doubles8 operator*(Doubles8 a, Doubles8 b) {
    return {_mm256_mul_pd(a.lo, b.lo), _mm256_mul_pd(a.hi, b.hi)};
  }
  friend Doubles8 operator/(Doubles8 a, Doubles8 b) {
    return {_mm256_div_pd(a.lo, b.lo), _mm256_div_pd(a.hi, b.hi)};
  }
  /// Lanes where x != 0 (NaN included).
  static unsigned nonZero(Doubles8 x) {
    const __m256d zero = _mm256_setzero_pd();
    const auto lo =
        static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(x.lo, zero, _CMP_NEQ_UQ)));
    const auto hi =
        static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(x.hi, zero, _CMP_NEQ_UQ)));
    return lo | (hi << 4);
  }
};

struct Lanes8 {
  static constexpr unsigned kWidth = 8;
  using Doubles = Doubles8;
  __m256 v;
  static Lanes8 load(const float* p) { return {_mm256_load_ps(p)}; }
  static Lanes8 broadcast(float x) { return {_mm256_set1_ps(x)}; }
  void store(float* p) const { _mm256_store_ps(p, v); }
  friend Lanes8 operator+(Lanes8 a, Lanes8 b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Lanes8 operator-(Lanes8 a, Lanes8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Lanes8 operator*(Lanes8 a, Lanes8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Lanes8 operator/(Lanes8 a, Lanes8 b) { return {_mm256_div_ps(a.v, b.v)}; }
  /// Rounds each double to the nearest float, as static_cast<float> does.
  static Lanes8 fromDoubles(Doubles8 x) {
    return {_mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(x.lo)),
                                 _mm256_cvtpd_ps(x.hi), 1)};
  }
  static unsigned mask(__m256 m) { return static_cast<unsigned>(_mm256_movemask_ps(m)); }
  static Lanes8 select(unsigned bits, Lanes8 a, Lanes8 b) {
    return {_mm256_blendv_ps(b.v, a.v, Avx8LaneOps::laneMask(bits))};
  }
  static unsigned anyZero(Lanes8 u, Lanes8 v, Lanes8 w) {
    const __m256 zero = _mm256_setzero_ps();
    return mask(_mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_EQ_OQ), _mm256_cmp_ps(v.v, zero, _CMP_EQ_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_EQ_OQ)));
  }
  static unsigned inside(Lanes8 u, Lanes8 v, Lanes8 w) {
    const __m256 zero = _mm256_setzero_ps();
    const __m256 anyNegative = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_LT_OQ), _mm256_cmp_ps(v.v, zero, _CMP_LT_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_LT_OQ));
    const __m256 anyPositive = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_GT_OQ), _mm256_cmp_ps(v.v, zero, _CMP_GT_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_GT_OQ));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(u.v, v.v), w.v);
    // NEQ_UQ: a NaN determinant goes on, as the scalar test's det == 0 lets it pass.
    return mask(_mm256_andnot_ps(_mm256_and_ps(anyNegative, anyPositive),
                                 _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ)));
  }
  static unsigned inRange(Lanes8 t, Lanes8 tnear, Lanes8 tfar) {
    const __m256 inf = _mm256_set1_ps(__builtin_inff());
    return mask(_mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(t.v, tnear.v, _CMP_GE_OQ),
                                            _mm256_cmp_ps(t.v, tfar.v, _CMP_LE_OQ)),
                              _mm256_cmp_ps(t.v, inf, _CMP_LT_OQ)));
  }
};

/// Rows of eight rays: row[j] holds float j (Ray's member order) of every ray, an 8 x 8
/// transpose. The rays are read by the unpacks themselves: copied into an array of registers
/// first, GCC moved them through the stack in 64-byte halves and read them back in 32-byte
/// quarters, which the store buffer cannot forward.
[[gnu::always_inline]] inline void transposeRays(const Ray* rays, __m256 (&row)[8]) {
  static_assert(sizeof(Ray) == 8 * sizeof(float) && kPacketLanes == 8,
                "eight rays of eight floats: an 8 x 8 transpose");
  const auto* f = reinterpret_cast<const float*>(rays);
  __m256 t[8], u[8];
  for (int i = 0; i < 8; i += 2) {
    const __m256 a = _mm256_loadu_ps(f + 8 * i), b = _mm256_loadu_ps(f + 8 * (i + 1));
    t[i] = _mm256_unpacklo_ps(a, b);
    t[i + 1] = _mm256_unpackhi_ps(a, b);
  }
  for (int i = 0; i < 8; i += 4) {
    u[i] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(1, 0, 1, 0));
    u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(3, 2, 3, 2));
    u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(1, 0, 1, 0));
    u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  for (int j = 0; j < 4; ++j) {
    row[j] = _mm256_permute2f128_ps(u[j], u[j + 4], 0x20);
    row[j + 4] = _mm256_permute2f128_ps(u[j], u[j + 4], 0x31);
  }
}

/// Writes lane `lead`'s value into every lane of the eight floats at `values` outside `keep`.
[[gnu::always_inline]] inline void spreadLane(float* values, __m256 keep, __m256i lead) {
  const __m256 v = _mm256_load_ps(values);
  _mm256_store_ps(values, _mm256_blendv_ps(_mm256_permutevar8x32_ps(v, lead), v, keep));
}

/// Gives every lane of the box rows outside `coherent` lane `lead`'s numbers (fillUnusedLanes).
[[gnu::always_inline]] inline void spreadBoxRows(PacketBoxRays& rays, unsigned coherent,
                                                 unsigned lead) {
  if (coherent == kAllLanes) return;
  const __m256 keep = Avx8LaneOps::laneMask(coherent);
  const __m256i leadIndex = _mm256_set1_epi32(static_cast<int>(lead));
  for (int a = 0; a < 3; ++a) {
    spreadLane(rays.origin[a], keep, leadIndex);
    spreadLane(rays.reciprocal[a], keep, leadIndex);
  }
  spreadLane(rays.tnear, keep, leadIndex);
  spreadLane(rays.tfar, keep, leadIndex);
}

/// The BoxRayLoadFn of the AVX kernels: loadPacketBoxRays (PacketRays.h) eight lanes per
/// instruction, with the same comparisons, minimum and division, so the same bits.
unsigned loadBoxRaysAvx(const Ray* rays, const Hit* hits, unsigned& lanes, PacketBoxRays& out) {
  __m256 row[8];
  transposeRays(rays, row);
  // The rows that go out unchanged are stored at once (unread when no lane is traceable): kept
  // until the end, GCC held them on the stack and copied them out in 64-byte moves from 32-byte
  // stores, which the store buffer cannot forward.
  for (int a = 0; a < 3; ++a) _mm256_store_ps(out.origin[a], row[a]);
  _mm256_store_ps(out.tnear, row[3]);
  // Traceable: finite origin and direction (|x| < inf is false for inf and NaN), a direction
  // that is not zero (unordered: NaN counts as not zero, and is caught above), tnear <= tfar.
  const __m256 absMask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  const __m256 inf = _mm256_set1_ps(__builtin_inff()), zero = _mm256_setzero_ps();
  __m256 ok = _mm256_cmp_ps(_mm256_and_ps(row[0], absMask), inf, _CMP_LT_OQ);
  for (int j : {1, 2, 4, 5, 6})
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(_mm256_and_ps(row[j], absMask), inf, _CMP_LT_OQ));
  const __m256 nonZero = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(row[4], zero, _CMP_NEQ_UQ),
                                                   _mm256_cmp_ps(row[5], zero, _CMP_NEQ_UQ)),
                                      _mm256_cmp_ps(row[6], zero, _CMP_NEQ_UQ));
  ok = _mm256_and_ps(_mm256_and_ps(ok, nonZero), _mm256_cmp_ps(row[3], row[7], _CMP_LE_OQ));
  lanes &= static_cast<unsigned>(_mm256_movemask_ps(ok));
  if (lanes == 0) return 0;
  const unsigned firstLane = static_cast<unsigned>(__builtin_ctz(lanes));
  unsigned coherent = lanes, signs = 0;
  for (int a = 0; a < 3; ++a) {
    // d < 0: not -0, not NaN, as directionSigns tests a component.
    const auto negative =
        static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(row[4 + a], zero, _CMP_LT_OQ)));
    const bool leadNegative = (negative >> firstLane) & 1u;
    signs |= (leadNegative ? 1u : 0u) << a;
    coherent &= leadNegative ? negative : ~negative;
  }
  if (hits) {
    // MINPS(t, tfar) is t < tfar ? t : tfar, which is std::min(tfar, t).
    const __m256 hitT = _mm256_setr_ps(hits[0].t, hits[1].t, hits[2].t, hits[3].t, hits[4].t,
                                       hits[5].t, hits[6].t, hits[7].t);
    row[7] = _mm256_min_ps(hitT, row[7]);
  }
  out.signs = signs;
  for (int a = 0; a < 3; ++a) {
    const __m256 d = row[4 + a];
    const __m256 reciprocal = _mm256_div_ps(_mm256_set1_ps(1.0f), d);
    _mm256_store_ps(out.reciprocal[a],
                    _mm256_blendv_ps(reciprocal, inf, _mm256_cmp_ps(d, zero, _CMP_EQ_OQ)));
  }
  _mm256_store_ps(out.tfar, row[7]);
  // Lanes of other signs take the first lane's values, in the rows as stored (the first lane's
  // reciprocal is what its direction gives), in place: the common case stores each row once.
  spreadBoxRows(out, coherent, firstLane);
  return coherent;
}

}  // namespace
}  // namespace tg::detail
