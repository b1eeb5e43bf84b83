// Eight lanes in an AVX register, for the triangle pre-filter of the AVX2 and AVX-512 kernels
// (see PacketTriangleFilter.h). Include only from translation units compiled with AVX2.
// Internal header: not installed.
#pragma once

#include <immintrin.h>

#include "PacketTriangleFilter.h"

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

struct Lanes8 {
  static constexpr unsigned kWidth = 8;
  __m256 v;
  static Lanes8 load(const float* p) { return {_mm256_load_ps(p)}; }
  static Lanes8 broadcast(float x) { return {_mm256_set1_ps(x)}; }
  friend Lanes8 operator+(Lanes8 a, Lanes8 b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Lanes8 operator-(Lanes8 a, Lanes8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Lanes8 operator*(Lanes8 a, Lanes8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
  static unsigned candidates(Lanes8 u, Lanes8 v, Lanes8 w) {
    const __m256 zero = _mm256_setzero_ps();
    const __m256 anyZero = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_EQ_OQ), _mm256_cmp_ps(v.v, zero, _CMP_EQ_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_EQ_OQ));
    const __m256 anyNegative = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_LT_OQ), _mm256_cmp_ps(v.v, zero, _CMP_LT_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_LT_OQ));
    const __m256 anyPositive = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u.v, zero, _CMP_GT_OQ), _mm256_cmp_ps(v.v, zero, _CMP_GT_OQ)),
        _mm256_cmp_ps(w.v, zero, _CMP_GT_OQ));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(u.v, v.v), w.v);
    // NEQ_UQ: a NaN determinant stays a candidate, as the scalar test's det == 0 lets it pass.
    const __m256 inside = _mm256_andnot_ps(_mm256_and_ps(anyNegative, anyPositive),
                                           _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
    return static_cast<unsigned>(_mm256_movemask_ps(_mm256_or_ps(anyZero, inside)));
  }
};

}  // namespace
}  // namespace tg::detail
