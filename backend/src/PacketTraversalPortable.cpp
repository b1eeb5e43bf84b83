// The portable packet kernel: SSE (the x86-64 baseline) tests one child box against four lanes
// per instruction; other targets use plain C++ with the same arithmetic.
#include "PacketTraversalImpl.h"
#include "PacketTriangleFilter.h"

#if TG_BVH4_SSE
#include <emmintrin.h>
#endif

namespace tg::detail {
namespace {

struct PortableNodeTest : ScalarLaneOps {
  /// No per-walk state.
  explicit PortableNodeTest(const PacketBoxRays&) {}
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
              _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(node.bounds[rays.nearRow[a]][s]), o), r);
          const __m128 f =
              _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(node.bounds[rays.farRow[a]][s]), o), r);
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
              (node.bounds[rays.nearRow[a]][s] - rays.origin[a][l]) * rays.reciprocal[a][l];
          const float f =
              (node.bounds[rays.farRow[a]][s] - rays.origin[a][l]) * rays.reciprocal[a][l];
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
/// Four lanes in an SSE register.
struct Lanes4 {
  static constexpr unsigned kWidth = 4;
  __m128 v;
  static Lanes4 load(const float* p) { return {_mm_load_ps(p)}; }
  static Lanes4 broadcast(float x) { return {_mm_set1_ps(x)}; }
  friend Lanes4 operator+(Lanes4 a, Lanes4 b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Lanes4 operator-(Lanes4 a, Lanes4 b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Lanes4 operator*(Lanes4 a, Lanes4 b) { return {_mm_mul_ps(a.v, b.v)}; }
  static unsigned candidates(Lanes4 u, Lanes4 v, Lanes4 w) {
    const __m128 zero = _mm_setzero_ps();
    const __m128 anyZero = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u.v, zero), _mm_cmpeq_ps(v.v, zero)),
                                     _mm_cmpeq_ps(w.v, zero));
    const __m128 anyNegative = _mm_or_ps(
        _mm_or_ps(_mm_cmplt_ps(u.v, zero), _mm_cmplt_ps(v.v, zero)), _mm_cmplt_ps(w.v, zero));
    const __m128 anyPositive = _mm_or_ps(
        _mm_or_ps(_mm_cmpgt_ps(u.v, zero), _mm_cmpgt_ps(v.v, zero)), _mm_cmpgt_ps(w.v, zero));
    const __m128 det = _mm_add_ps(_mm_add_ps(u.v, v.v), w.v);
    const __m128 inside =
        _mm_andnot_ps(_mm_and_ps(anyNegative, anyPositive), _mm_cmpneq_ps(det, zero));
    return static_cast<unsigned>(_mm_movemask_ps(_mm_or_ps(anyZero, inside)));
  }
};
using PortableLanes = Lanes4;
#else
/// One lane in a float.
struct Lanes1 {
  static constexpr unsigned kWidth = 1;
  float v;
  static Lanes1 load(const float* p) { return {*p}; }
  static Lanes1 broadcast(float x) { return {x}; }
  friend Lanes1 operator+(Lanes1 a, Lanes1 b) { return {a.v + b.v}; }
  friend Lanes1 operator-(Lanes1 a, Lanes1 b) { return {a.v - b.v}; }
  friend Lanes1 operator*(Lanes1 a, Lanes1 b) { return {a.v * b.v}; }
  static unsigned candidates(Lanes1 u, Lanes1 v, Lanes1 w) {
    if (u.v == 0.0f || v.v == 0.0f || w.v == 0.0f) return 1;
    const bool mixed =
        (u.v < 0.0f || v.v < 0.0f || w.v < 0.0f) && (u.v > 0.0f || v.v > 0.0f || w.v > 0.0f);
    return !mixed && u.v + v.v + w.v != 0.0f ? 1 : 0;
  }
};
using PortableLanes = Lanes1;
#endif

}  // namespace

PacketKernels packetKernelsPortable() {
  return packetKernelsWith<PortableNodeTest, PortableLanes>();
}

}  // namespace tg::detail
