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
  /// Smallest entry[l] over the lanes l in `mask` (not empty). The lanes of a hit slot hold no
  /// NaN (their entry passed tmin <= tmax), so MINPS gives the scalar loop's value.
  static float minEntry(const float* entry, unsigned mask) {
    const __m256 inf = _mm256_set1_ps(__builtin_inff());
    __m256 v = _mm256_blendv_ps(inf, _mm256_loadu_ps(entry), laneMask(mask));
    v = _mm256_min_ps(v, _mm256_permute2f128_ps(v, v, 1));
    v = _mm256_min_ps(v, _mm256_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
    v = _mm256_min_ps(v, _mm256_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm256_cvtss_f32(v);
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

}  // namespace
}  // namespace tg::detail
