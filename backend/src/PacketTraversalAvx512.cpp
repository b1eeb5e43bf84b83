// The AVX-512 packet kernel: one instruction tests two child boxes against all eight lanes
// (low half: slot s, high half: slot s + 1). Compiled with -mavx512f -ffp-contract=off (see
// backend/CMakeLists.txt and PacketTraversalAvx2.cpp for why contraction is off).
#include "PacketKernel.h"

#if defined(__AVX512F__)
// GCC 12's AVX-512 intrinsics trip -Wmaybe-uninitialized and -Wuninitialized on their own
// internal placeholder operands once inlined (GCC bug 105593, fixed in GCC 13); the warnings
// say nothing about this file's code.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include "PacketLanesAvx.h"
#include "PacketObjectRowsAvx.h"
#include "PacketOneBox8.h"
#include "PacketPairWalkImpl.h"
#include "PacketTraversalImpl.h"

namespace tg::detail {
namespace {

/// The eight lanes of `p` in both halves of a 16-float register.
inline __m512 duplicateLanes(const float* p) {
  const __m512i index = _mm512_set_epi32(7, 6, 5, 4, 3, 2, 1, 0, 7, 6, 5, 4, 3, 2, 1, 0);
  return _mm512_permutexvar_ps(index, _mm512_zextps256_ps512(_mm256_load_ps(p)));
}

/// Plane value of slot s in the low half, of slot s + 1 in the high half.
inline __m512 slotPair(const float* row, int s) {
  return _mm512_mask_blend_ps(0xFF00, _mm512_set1_ps(row[s]), _mm512_set1_ps(row[s + 1]));
}

struct Avx512NodeTest : Avx8LaneOps {
  /// The widening of the box intervals follows the tnear sign.
  static constexpr bool kReadsTnearSign = true;
  /// The rays' fixed values with their lanes duplicated into both halves, once per walk: the
  /// permutes would otherwise be a quarter of every node test. tfar changes during the walk and
  /// is read per node.
  explicit Avx512NodeTest(const PacketBoxRays& rays) : tnear(duplicateLanes(rays.tnear)) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = duplicateLanes(rays.origin[a]);
      reciprocal[a] = duplicateLanes(rays.reciprocal[a]);
    }
  }

  __m512 tnear;
  __m512 origin[3], reciprocal[3];

  template <class Rows>
  void test(const Bvh4Node& node, const PacketBoxRays& rays, unsigned lanes, unsigned hit[4],
            float entry[4][kPacketLanes]) const {
    const __m512i absMask = _mm512_set1_epi32(0x7FFFFFFF);
    const __m512 slack = _mm512_set1_ps(kBvhIntervalSlack);
    const __m512 tfar = duplicateLanes(rays.tfar);
    for (int s = 0; s < 4; s += 2) {
      __m512 tmin = tnear, tmax = tfar;
      for (int a = 0; a < 3; ++a) {
        const __m512 n = _mm512_mul_ps(
            _mm512_sub_ps(slotPair(node.bounds[Rows::nearRow(a)], s), origin[a]), reciprocal[a]);
        const __m512 f = _mm512_mul_ps(
            _mm512_sub_ps(slotPair(node.bounds[Rows::farRow(a)], s), origin[a]), reciprocal[a]);
        tmin = _mm512_max_ps(n, tmin);
        tmax = _mm512_min_ps(f, tmax);
      }
      if constexpr (Rows::nonNegativeTnear) {
        tmin = _mm512_mul_ps(tmin, _mm512_set1_ps(1.0f - kBvhIntervalSlack));
        tmax = _mm512_mul_ps(tmax, _mm512_set1_ps(1.0f + kBvhIntervalSlack));
      } else {
        const __m512 absMin =
            _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(tmin), absMask));
        const __m512 absMax =
            _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(tmax), absMask));
        tmin = _mm512_sub_ps(tmin, _mm512_mul_ps(absMin, slack));
        tmax = _mm512_add_ps(tmax, _mm512_mul_ps(absMax, slack));
      }
      // entry[s] and entry[s + 1] are adjacent: one store fills both.
      _mm512_store_ps(entry[s], tmin);
      const unsigned mask = _mm512_cmp_ps_mask(tmin, tmax, _CMP_LE_OS);
      hit[s] = mask & lanes;
      hit[s + 1] = (mask >> 8) & lanes;
    }
  }
};

/// Sixteen doubles in two AVX-512 registers (lanes 0-7, 8-15).
struct Doubles16 {
  __m512d lo, hi;
  static Doubles16 load(const double* p) { return {_mm512_load_pd(p), _mm512_load_pd(p + 8)}; }
  static Doubles16 broadcast(double x) { return {_mm512_set1_pd(x), _mm512_set1_pd(x)}; }
  friend Doubles16 operator+(Doubles16 a, Doubles16 b) {
    return {_mm512_add_pd(a.lo, b.lo), _mm512_add_pd(a.hi, b.hi)};
  }
  friend Doubles16 operator-(Doubles16 a, Doubles16 b) {
    return {_mm512_sub_pd(a.lo, b.lo), _mm512_sub_pd(a.hi, b.hi)};
  }
  friend Doubles16 operator*(Doubles16 a, Doubles16 b) {
    return {_mm512_mul_pd(a.lo, b.lo), _mm512_mul_pd(a.hi, b.hi)};
  }
  friend Doubles16 operator/(Doubles16 a, Doubles16 b) {
    return {_mm512_div_pd(a.lo, b.lo), _mm512_div_pd(a.hi, b.hi)};
  }
  /// Lanes where x != 0 (NaN included).
  static unsigned nonZero(Doubles16 x) {
    const __m512d zero = _mm512_setzero_pd();
    return static_cast<unsigned>(_mm512_cmp_pd_mask(x.lo, zero, _CMP_NEQ_UQ)) |
           static_cast<unsigned>(_mm512_cmp_pd_mask(x.hi, zero, _CMP_NEQ_UQ)) << 8;
  }
};

/// Sixteen lanes in one AVX-512 register, for the pair triangle test (PacketTriangleTest.h):
/// Lanes8's operations and comparisons at twice the width, so each lane's bits are the same.
struct Lanes16 {
  static constexpr unsigned kWidth = 16;
  using Doubles = Doubles16;
  __m512 v;
  static Lanes16 load(const float* p) { return {_mm512_load_ps(p)}; }
  static Lanes16 broadcast(float x) { return {_mm512_set1_ps(x)}; }
  void store(float* p) const { _mm512_store_ps(p, v); }
  friend Lanes16 operator+(Lanes16 a, Lanes16 b) { return {_mm512_add_ps(a.v, b.v)}; }
  friend Lanes16 operator-(Lanes16 a, Lanes16 b) { return {_mm512_sub_ps(a.v, b.v)}; }
  friend Lanes16 operator*(Lanes16 a, Lanes16 b) { return {_mm512_mul_ps(a.v, b.v)}; }
  friend Lanes16 operator/(Lanes16 a, Lanes16 b) { return {_mm512_div_ps(a.v, b.v)}; }
  /// Rounds each double to the nearest float, as static_cast<float> does.
  static Lanes16 fromDoubles(Doubles16 x) {
    return {_mm512_castpd_ps(
        _mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(_mm512_cvtpd_ps(x.lo))),
                           _mm256_castps_pd(_mm512_cvtpd_ps(x.hi)), 1))};
  }
  static Lanes16 select(unsigned bits, Lanes16 a, Lanes16 b) {
    return {_mm512_mask_blend_ps(static_cast<__mmask16>(bits), b.v, a.v)};
  }
  static unsigned anyZero(Lanes16 u, Lanes16 v, Lanes16 w) {
    const __m512 zero = _mm512_setzero_ps();
    return static_cast<unsigned>(_mm512_cmp_ps_mask(u.v, zero, _CMP_EQ_OQ) |
                                 _mm512_cmp_ps_mask(v.v, zero, _CMP_EQ_OQ) |
                                 _mm512_cmp_ps_mask(w.v, zero, _CMP_EQ_OQ));
  }
  static unsigned inside(Lanes16 u, Lanes16 v, Lanes16 w) {
    const __m512 zero = _mm512_setzero_ps();
    const unsigned anyNegative = _mm512_cmp_ps_mask(u.v, zero, _CMP_LT_OQ) |
                                 _mm512_cmp_ps_mask(v.v, zero, _CMP_LT_OQ) |
                                 _mm512_cmp_ps_mask(w.v, zero, _CMP_LT_OQ);
    const unsigned anyPositive = _mm512_cmp_ps_mask(u.v, zero, _CMP_GT_OQ) |
                                 _mm512_cmp_ps_mask(v.v, zero, _CMP_GT_OQ) |
                                 _mm512_cmp_ps_mask(w.v, zero, _CMP_GT_OQ);
    const __m512 det = _mm512_add_ps(_mm512_add_ps(u.v, v.v), w.v);
    // NEQ_UQ: a NaN determinant goes on, as the scalar test's det == 0 lets it pass.
    return ~(anyNegative & anyPositive) &
           static_cast<unsigned>(_mm512_cmp_ps_mask(det, zero, _CMP_NEQ_UQ));
  }
  static unsigned inRange(Lanes16 t, Lanes16 tnear, Lanes16 tfar) {
    const __m512 inf = _mm512_set1_ps(__builtin_inff());
    return static_cast<unsigned>(_mm512_cmp_ps_mask(t.v, tnear.v, _CMP_GE_OQ) &
                                 _mm512_cmp_ps_mask(t.v, tfar.v, _CMP_LE_OQ) &
                                 _mm512_cmp_ps_mask(t.v, inf, _CMP_LT_OQ));
  }
};

/// The rows of both halves of a pair in one register: half 0's lanes low, half 1's high.
inline __m512 pairRow(const float* low, const float* high) {
  // insertf64x4 is AVX-512F (insertf32x8 would need DQ); moving bits, the lane type is moot.
  return _mm512_castpd_ps(
      _mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(_mm256_load_ps(low))),
                         _mm256_castps_pd(_mm256_load_ps(high)), 1));
}

/// The pair walk's node test (PacketPairWalkImpl.h): one slot of the node against all sixteen
/// lanes per instruction, with Avx512NodeTest's arithmetic in the same order, so each lane's
/// entry and hit are the bits its own packet's walk computes.
struct Avx512PairNodeTest {
  explicit Avx512PairNodeTest(PacketBoxRays* const (&rays)[2])
      : tnear(pairRow(rays[0]->tnear, rays[1]->tnear)) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = pairRow(rays[0]->origin[a], rays[1]->origin[a]);
      reciprocal[a] = pairRow(rays[0]->reciprocal[a], rays[1]->reciprocal[a]);
    }
  }

  __m512 tnear;
  __m512 origin[3], reciprocal[3];

  static __m512 tfar(PacketBoxRays* const (&rays)[2]) {
    return pairRow(rays[0]->tfar, rays[1]->tfar);
  }

  /// The lanes l of `mask` whose entry[l] lies beyond their tfar (ordered: false for NaN).
  static unsigned beyond(const float* entry, PacketBoxRays* const (&rays)[2], unsigned mask) {
    return _mm512_mask_cmp_ps_mask(static_cast<__mmask16>(mask), _mm512_load_ps(entry), tfar(rays),
                                   _CMP_GT_OQ);
  }

  static void copyEntry(const float* from, float* to) { _mm512_store_ps(to, _mm512_load_ps(from)); }

  template <class Rows>
  void test(const Bvh4Node& node, PacketBoxRays* const (&rays)[2], unsigned lanes, unsigned hit[4],
            float entry[4][kPairLanes]) const {
    const __m512i absMask = _mm512_set1_epi32(0x7FFFFFFF);
    const __m512 slack = _mm512_set1_ps(kBvhIntervalSlack);
    const __m512 far = tfar(rays);
    for (int s = 0; s < 4; ++s) {
      __m512 tmin = tnear, tmax = far;
      for (int a = 0; a < 3; ++a) {
        const __m512 n = _mm512_mul_ps(
            _mm512_sub_ps(_mm512_set1_ps(node.bounds[Rows::nearRow(a)][s]), origin[a]),
            reciprocal[a]);
        const __m512 f =
            _mm512_mul_ps(_mm512_sub_ps(_mm512_set1_ps(node.bounds[Rows::farRow(a)][s]), origin[a]),
                          reciprocal[a]);
        tmin = _mm512_max_ps(n, tmin);
        tmax = _mm512_min_ps(f, tmax);
      }
      if constexpr (Rows::nonNegativeTnear) {
        tmin = _mm512_mul_ps(tmin, _mm512_set1_ps(1.0f - kBvhIntervalSlack));
        tmax = _mm512_mul_ps(tmax, _mm512_set1_ps(1.0f + kBvhIntervalSlack));
      } else {
        const __m512 absMin =
            _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(tmin), absMask));
        const __m512 absMax =
            _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(tmax), absMask));
        tmin = _mm512_sub_ps(tmin, _mm512_mul_ps(absMin, slack));
        tmax = _mm512_add_ps(tmax, _mm512_mul_ps(absMax, slack));
      }
      _mm512_store_ps(entry[s], tmin);
      hit[s] = _mm512_mask_cmp_ps_mask(static_cast<__mmask16>(lanes), tmin, tmax, _CMP_LE_OS);
    }
  }
};

}  // namespace

PacketKernels packetKernelsAvx512() {
  PacketKernels kernels = packetKernelsWith<Avx512NodeTest, Lanes8>(
      &loadBoxRaysAvx, &loadTransformedRowsAvx, &loadIdentityRowsAvx, &meetsOneBoxAvx);
  kernels.traversePair = &traversePair<Avx512PairNodeTest>;
  kernels.occludedPair = &occludedPair<Avx512PairNodeTest>;
  kernels.testTrianglesPair = &testTrianglesPairWith<Lanes16>;
  return kernels;
}

}  // namespace tg::detail
#else
namespace tg::detail {
PacketKernels packetKernelsAvx512() {
  return {};
}
}  // namespace tg::detail
#endif
