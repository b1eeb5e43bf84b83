// The portable packet kernel: SSE (the x86-64 baseline) tests one child box against four lanes
// per instruction; other targets use plain C++ with the same arithmetic.
#include "PacketRays.h"
#include "PacketTransformedRays.h"
#include "PacketTraversalImpl.h"
#include "PacketTriangleTest.h"

#if TG_BVH4_SSE
#include <emmintrin.h>
#endif

namespace tg::detail {
namespace {

struct PortableNodeTest : ScalarLaneOps {
  /// The widening is the same whatever the tnear sign: no walk per sign.
  static constexpr bool kReadsTnearSign = false;
  /// No per-walk state.
  explicit PortableNodeTest(const PacketBoxRays&) {}
  template <class Rows>
  static void test(const Bvh4Node& node, const PacketBoxRays& rays, unsigned lanes, unsigned hit[4],
                   float entry[4][kPacketLanes]) {
#if TG_BVH4_SSE
    const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    const __m128 slack = _mm_set1_ps(kBvhIntervalSlack);
    for (int s = 0; s < 4; ++s) {
      unsigned mask = 0;
      for (unsigned h = 0; h < kPacketLanes; h += 4) {
        __m128 tmin = _mm_load_ps(rays.tnear + h), tmax = _mm_load_ps(rays.tfar + h);
        for (int a = 0; a < 3; ++a) {
          const __m128 o = _mm_load_ps(rays.origin[a] + h);
          const __m128 r = _mm_load_ps(rays.reciprocal[a] + h);
          const __m128 n =
              _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(node.bounds[Rows::nearRow(a)][s]), o), r);
          const __m128 f =
              _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(node.bounds[Rows::farRow(a)][s]), o), r);
          tmin = _mm_max_ps(n, tmin);
          tmax = _mm_min_ps(f, tmax);
        }
        tmin = _mm_sub_ps(tmin, _mm_mul_ps(_mm_and_ps(tmin, absMask), slack));
        tmax = _mm_add_ps(tmax, _mm_mul_ps(_mm_and_ps(tmax, absMask), slack));
        _mm_store_ps(entry[s] + h, tmin);
        mask |= static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(tmin, tmax))) << h;
      }
      hit[s] = mask & lanes;
    }
#else
    for (int s = 0; s < 4; ++s) {
      unsigned mask = 0;
      for (unsigned l = 0; l < kPacketLanes; ++l) {
        float tmin = rays.tnear[l], tmax = rays.tfar[l];
        for (int a = 0; a < 3; ++a) {
          const float n =
              (node.bounds[Rows::nearRow(a)][s] - rays.origin[a][l]) * rays.reciprocal[a][l];
          const float f =
              (node.bounds[Rows::farRow(a)][s] - rays.origin[a][l]) * rays.reciprocal[a][l];
          tmin = n > tmin ? n : tmin;
          tmax = f < tmax ? f : tmax;
        }
        tmin -= (tmin < 0.0f ? -tmin : tmin) * kBvhIntervalSlack;
        tmax += (tmax < 0.0f ? -tmax : tmax) * kBvhIntervalSlack;
        entry[s][l] = tmin;
        if (tmin <= tmax) mask |= 1u << l;
      }
      hit[s] = mask & lanes;
    }
#endif
  }
};

#if TG_BVH4_SSE
/// Four doubles in two SSE registers (lanes 0-1, 2-3).
struct Doubles4 {
  __m128d lo, hi;
  static Doubles4 load(const double* p) { return {_mm_load_pd(p), _mm_load_pd(p + 2)}; }
  static Doubles4 broadcast(double x) { return {_mm_set1_pd(x), _mm_set1_pd(x)}; }
  friend Doubles4 operator+(Doubles4 a, Doubles4 b) {
    return {_mm_add_pd(a.lo, b.lo), _mm_add_pd(a.hi, b.hi)};
  }
  friend Doubles4 operator-(Doubles4 a, Doubles4 b) {
    return {_mm_sub_pd(a.lo, b.lo), _mm_sub_pd(a.hi, b.hi)};
  }
  friend Doubles4 operator*(Doubles4 a, Doubles4 b) {
    return {_mm_mul_pd(a.lo, b.lo), _mm_mul_pd(a.hi, b.hi)};
  }
  friend Doubles4 operator/(Doubles4 a, Doubles4 b) {
    return {_mm_div_pd(a.lo, b.lo), _mm_div_pd(a.hi, b.hi)};
  }
  /// Lanes where x != 0 (NaN included).
  static unsigned nonZero(Doubles4 x) {
    const __m128d zero = _mm_setzero_pd();
    const auto lo = static_cast<unsigned>(_mm_movemask_pd(_mm_cmpneq_pd(x.lo, zero)));
    const auto hi = static_cast<unsigned>(_mm_movemask_pd(_mm_cmpneq_pd(x.hi, zero)));
    return lo | (hi << 2);
  }
};

/// Four lanes in an SSE register.
struct Lanes4 {
  static constexpr unsigned kWidth = 4;
  using Doubles = Doubles4;
  __m128 v;
  static Lanes4 load(const float* p) { return {_mm_load_ps(p)}; }
  static Lanes4 broadcast(float x) { return {_mm_set1_ps(x)}; }
  void store(float* p) const { _mm_store_ps(p, v); }
  friend Lanes4 operator+(Lanes4 a, Lanes4 b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Lanes4 operator-(Lanes4 a, Lanes4 b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Lanes4 operator*(Lanes4 a, Lanes4 b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Lanes4 operator/(Lanes4 a, Lanes4 b) { return {_mm_div_ps(a.v, b.v)}; }
  /// Rounds each double to the nearest float, as static_cast<float> does.
  static Lanes4 fromDoubles(Doubles4 x) {
    return {_mm_movelh_ps(_mm_cvtpd_ps(x.lo), _mm_cvtpd_ps(x.hi))};
  }
  static unsigned mask(__m128 m) { return static_cast<unsigned>(_mm_movemask_ps(m)); }
  static Lanes4 select(unsigned bits, Lanes4 a, Lanes4 b) {
    const __m128i lane = _mm_setr_epi32(1, 2, 4, 8);
    const __m128 m = _mm_castsi128_ps(
        _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(static_cast<int>(bits)), lane), lane));
    return {_mm_or_ps(_mm_and_ps(m, a.v), _mm_andnot_ps(m, b.v))};
  }
  static unsigned anyZero(Lanes4 u, Lanes4 v, Lanes4 w) {
    const __m128 zero = _mm_setzero_ps();
    return mask(_mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u.v, zero), _mm_cmpeq_ps(v.v, zero)),
                          _mm_cmpeq_ps(w.v, zero)));
  }
  static unsigned inside(Lanes4 u, Lanes4 v, Lanes4 w) {
    const __m128 zero = _mm_setzero_ps();
    const __m128 anyNegative = _mm_or_ps(
        _mm_or_ps(_mm_cmplt_ps(u.v, zero), _mm_cmplt_ps(v.v, zero)), _mm_cmplt_ps(w.v, zero));
    const __m128 anyPositive = _mm_or_ps(
        _mm_or_ps(_mm_cmpgt_ps(u.v, zero), _mm_cmpgt_ps(v.v, zero)), _mm_cmpgt_ps(w.v, zero));
    const __m128 det = _mm_add_ps(_mm_add_ps(u.v, v.v), w.v);
    // cmpneq is unordered: a NaN determinant goes on, as in the scalar test.
    return mask(_mm_andnot_ps(_mm_and_ps(anyNegative, anyPositive), _mm_cmpneq_ps(det, zero)));
  }
  static unsigned inRange(Lanes4 t, Lanes4 tnear, Lanes4 tfar) {
    const __m128 inf = _mm_set1_ps(__builtin_inff());
    return mask(_mm_and_ps(_mm_and_ps(_mm_cmpge_ps(t.v, tnear.v), _mm_cmple_ps(t.v, tfar.v)),
                           _mm_cmplt_ps(t.v, inf)));
  }
};
using PortableLanes = Lanes4;
#else
/// One double.
struct Doubles1 {
  double v;
  static Doubles1 load(const double* p) { return {*p}; }
  static Doubles1 broadcast(double x) { return {x}; }
  friend Doubles1 operator+(Doubles1 a, Doubles1 b) { return {a.v + b.v}; }
  friend Doubles1 operator-(Doubles1 a, Doubles1 b) { return {a.v - b.v}; }
  friend Doubles1 operator*(Doubles1 a, Doubles1 b) { return {a.v * b.v}; }
  friend Doubles1 operator/(Doubles1 a, Doubles1 b) { return {a.v / b.v}; }
  static unsigned nonZero(Doubles1 x) { return x.v != 0.0 ? 1 : 0; }
};

/// One lane in a float.
struct Lanes1 {
  static constexpr unsigned kWidth = 1;
  using Doubles = Doubles1;
  float v;
  static Lanes1 load(const float* p) { return {*p}; }
  static Lanes1 broadcast(float x) { return {x}; }
  void store(float* p) const { *p = v; }
  friend Lanes1 operator+(Lanes1 a, Lanes1 b) { return {a.v + b.v}; }
  friend Lanes1 operator-(Lanes1 a, Lanes1 b) { return {a.v - b.v}; }
  friend Lanes1 operator*(Lanes1 a, Lanes1 b) { return {a.v * b.v}; }
  friend Lanes1 operator/(Lanes1 a, Lanes1 b) { return {a.v / b.v}; }
  static Lanes1 fromDoubles(Doubles1 x) { return {static_cast<float>(x.v)}; }
  static Lanes1 select(unsigned bits, Lanes1 a, Lanes1 b) { return (bits & 1u) ? a : b; }
  static unsigned anyZero(Lanes1 u, Lanes1 v, Lanes1 w) {
    return u.v == 0.0f || v.v == 0.0f || w.v == 0.0f ? 1 : 0;
  }
  static unsigned inside(Lanes1 u, Lanes1 v, Lanes1 w) {
    const bool mixed =
        (u.v < 0.0f || v.v < 0.0f || w.v < 0.0f) && (u.v > 0.0f || v.v > 0.0f || w.v > 0.0f);
    return !mixed && u.v + v.v + w.v != 0.0f ? 1 : 0;
  }
  static unsigned inRange(Lanes1 t, Lanes1 tnear, Lanes1 tfar) {
    return t.v >= tnear.v && t.v <= tfar.v && t.v < __builtin_inff() ? 1 : 0;
  }
};
using PortableLanes = Lanes1;
#endif

/// The portable PacketOneBoxFn: PortableNodeTest's arithmetic lane by lane for the one slot.
unsigned meetsOneBoxPortable(const Bvh4Node& node, const PacketBoxRays& rays, unsigned lanes) {
  unsigned mask = 0;
  for (unsigned l = 0; l < kPacketLanes; ++l) {
    float tmin = rays.tnear[l], tmax = rays.tfar[l];
    for (int a = 0; a < 3; ++a) {
      const auto negative = static_cast<int>((rays.signs >> a) & 1u);
      const float n =
          (node.bounds[2 * a + negative][0] - rays.origin[a][l]) * rays.reciprocal[a][l];
      const float f =
          (node.bounds[2 * a + 1 - negative][0] - rays.origin[a][l]) * rays.reciprocal[a][l];
      // Written so that NaN keeps the interval, as MAXPS and MINPS do.
      tmin = n > tmin ? n : tmin;
      tmax = f < tmax ? f : tmax;
    }
    tmin -= (tmin < 0.0f ? -tmin : tmin) * kBvhIntervalSlack;
    tmax += (tmax < 0.0f ? -tmax : tmax) * kBvhIntervalSlack;
    if (tmin <= tmax) mask |= 1u << l;
  }
  return mask & lanes;
}

}  // namespace

PacketKernels packetKernelsPortable() {
  return packetKernelsWith<PortableNodeTest, PortableLanes>(
      &loadPacketBoxRays, &loadTransformedRows, &loadIdentityRows, &meetsOneBoxPortable);
}

}  // namespace tg::detail
