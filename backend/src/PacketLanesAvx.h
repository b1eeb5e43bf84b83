// Eight lanes in an AVX register, for the triangle pre-filter of the AVX2 and AVX-512 kernels
// (see PacketTriangleFilter.h). Include only from translation units compiled with AVX2.
// Internal header: not installed.
#pragma once

#include <immintrin.h>

#include "PacketTriangleFilter.h"

namespace tg::detail {
namespace {

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
