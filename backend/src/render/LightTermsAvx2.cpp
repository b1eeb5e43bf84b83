// The point-light terms eight lights at a time with AVX (pointLightTermsWith over 256-bit
// lanes), and their sums at eight surface points at a time (pointLightSumsWith). Compiled with
// -mavx2 -ffp-contract=off (see backend/CMakeLists.txt): every lane rounds exactly as the
// baseline's four-light terms do. Only plain data and this file's own functions are used here (see
// LightTerms.h for why).
#include "LightTerms.h"

#if defined(__AVX2__)
#include <immintrin.h>

#include "PointLightTermsImpl.h"

namespace tg::detail {
namespace {

/// Eight floats, one per light of a PointLightGroup<8> (the operations of Lanes4 in
/// Shading.cpp, eight lanes wide).
struct Lanes8 {
  static constexpr std::size_t kWidth = 8;
  __m256 v;

  static Lanes8 load(const float* a) { return {_mm256_loadu_ps(a)}; }
  static Lanes8 splat(float f) { return {_mm256_set1_ps(f)}; }
  template <typename F>
  static Lanes8 fromScalars(const F& f) {
    return {_mm256_setr_ps(f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7))};
  }
  static void store(const Lanes8& a, float* out) { _mm256_storeu_ps(out, a.v); }
  /// A true/false per lane (all bits set or clear).
  struct Mask {
    __m256 v;
  };
  static Mask allLanes(bool on) { return {_mm256_castsi256_ps(_mm256_set1_epi32(on ? -1 : 0))}; }
  /// Lane j true when bit j of `b` is set.
  static Mask fromBits(unsigned b) {
    const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i set = _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), lane);
    return {_mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lane))};
  }
};
Lanes8 operator+(Lanes8 a, Lanes8 b) {
  return {_mm256_add_ps(a.v, b.v)};
}
Lanes8 operator-(Lanes8 a, Lanes8 b) {
  return {_mm256_sub_ps(a.v, b.v)};
}
Lanes8 operator*(Lanes8 a, Lanes8 b) {
  return {_mm256_mul_ps(a.v, b.v)};
}
Lanes8 operator/(Lanes8 a, Lanes8 b) {
  return {_mm256_div_ps(a.v, b.v)};
}
Lanes8 sqrt(Lanes8 a) {
  return {_mm256_sqrt_ps(a.v)};
}
// The SSE comparisons' predicates: ordered and quiet, false for NaN lanes.
Lanes8::Mask operator>(Lanes8 a, Lanes8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OS)};
}
Lanes8::Mask operator>=(Lanes8 a, Lanes8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OS)};
}
Lanes8::Mask operator<=(Lanes8 a, Lanes8 b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OS)};
}
Lanes8::Mask operator|(Lanes8::Mask a, Lanes8::Mask b) {
  return {_mm256_or_ps(a.v, b.v)};
}
Lanes8::Mask operator&(Lanes8::Mask a, Lanes8::Mask b) {
  return {_mm256_and_ps(a.v, b.v)};
}
/// a and not b.
Lanes8::Mask andNot(Lanes8::Mask a, Lanes8::Mask b) {
  return {_mm256_andnot_ps(b.v, a.v)};
}
/// Bit j set when lane j is true.
unsigned bits(Lanes8::Mask m) {
  return static_cast<unsigned>(_mm256_movemask_ps(m.v));
}
/// a where m is true, b elsewhere.
Lanes8 select(Lanes8::Mask m, Lanes8 a, Lanes8 b) {
  return {_mm256_blendv_ps(b.v, a.v, m.v)};
}
/// out[j] = (r[j], g[j], b[j], 0): lane j's colour as one 16-byte store.
void storeColors(Lanes8 r, Lanes8 g, Lanes8 b, float (&out)[8][4]) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 rgLow = _mm256_unpacklo_ps(r.v, g.v), rgHigh = _mm256_unpackhi_ps(r.v, g.v);
  const __m256 b0Low = _mm256_unpacklo_ps(b.v, zero), b0High = _mm256_unpackhi_ps(b.v, zero);
  // Per 128-bit half h: lanes 4h + 0 .. 4h + 3.
  const __m256 c0 = _mm256_shuffle_ps(rgLow, b0Low, _MM_SHUFFLE(1, 0, 1, 0));
  const __m256 c1 = _mm256_shuffle_ps(rgLow, b0Low, _MM_SHUFFLE(3, 2, 3, 2));
  const __m256 c2 = _mm256_shuffle_ps(rgHigh, b0High, _MM_SHUFFLE(1, 0, 1, 0));
  const __m256 c3 = _mm256_shuffle_ps(rgHigh, b0High, _MM_SHUFFLE(3, 2, 3, 2));
  _mm_storeu_ps(out[0], _mm256_castps256_ps128(c0));
  _mm_storeu_ps(out[1], _mm256_castps256_ps128(c1));
  _mm_storeu_ps(out[2], _mm256_castps256_ps128(c2));
  _mm_storeu_ps(out[3], _mm256_castps256_ps128(c3));
  _mm_storeu_ps(out[4], _mm256_extractf128_ps(c0, 1));
  _mm_storeu_ps(out[5], _mm256_extractf128_ps(c1, 1));
  _mm_storeu_ps(out[6], _mm256_extractf128_ps(c2, 1));
  _mm_storeu_ps(out[7], _mm256_extractf128_ps(c3, 1));
}

void pointLightTerms8(const PointLightGroup<8>& group, std::size_t count, const LightTermsPoint& p,
                      LightGroupTerms<8>& out) {
  // The groups handed here have no attenuated light.
  const auto none = [](const Lanes8&, Lanes8&, Lanes8&, Lanes8&) {};
  pointLightTermsWith<Lanes8>(group, count, p, none, out);
}

void pointLightSums8(const PlainPointLight* lights, std::size_t count,
                     SurfacePointLanes<8>& points) {
  // Only lights without attenuation are handed here.
  const auto none = [](std::size_t, const Lanes8&, Lanes8&, Lanes8&, Lanes8&) {};
  pointLightSumsWith<Lanes8>(lights, count, points, none);
}

}  // namespace

PointLightTerms8Fn pointLightTermsAvx2() {
  return &pointLightTerms8;
}

PointLightSums8Fn pointLightSumsAvx2() {
  return &pointLightSums8;
}

}  // namespace tg::detail
#else
namespace tg::detail {
PointLightTerms8Fn pointLightTermsAvx2() {
  return nullptr;
}
PointLightSums8Fn pointLightSumsAvx2() {
  return nullptr;
}
}  // namespace tg::detail
#endif
