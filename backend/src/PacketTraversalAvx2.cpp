// The AVX2 packet kernel: one instruction tests a child box against all eight lanes. Compiled
// with -mavx2 -mfma -ffp-contract=off (see backend/CMakeLists.txt): contraction would fuse the
// slab products into FMAs and round differently from the single-ray test.
#include "PacketKernel.h"

#if defined(__AVX2__)
#include <immintrin.h>

#include "PacketLanesAvx.h"
#include "PacketObjectRowsAvx.h"
#include "PacketOneBox8.h"
#include "PacketPairWalkImpl.h"
#include "PacketTraversalImpl.h"
#include "SlabWidening8.h"

namespace tg::detail {
namespace {

/// The lanes whose widened slab interval of box `s` of `node` is not empty, with
/// intersectBvh4Node's arithmetic in its order; each lane's entry (tmin) goes to `entry`.
template <class Rows>
[[gnu::always_inline]] inline unsigned slabTest8(const Bvh4Node& node, int s,
                                                 const __m256 (&origin)[3],
                                                 const __m256 (&reciprocal)[3], __m256 tnear,
                                                 __m256 tfar, float* entry) {
  __m256 tmin = tnear, tmax = tfar;
  for (int a = 0; a < 3; ++a) {
    const __m256 n = _mm256_mul_ps(
        _mm256_sub_ps(_mm256_set1_ps(node.bounds[Rows::nearRow(a)][s]), origin[a]), reciprocal[a]);
    const __m256 f = _mm256_mul_ps(
        _mm256_sub_ps(_mm256_set1_ps(node.bounds[Rows::farRow(a)][s]), origin[a]), reciprocal[a]);
    tmin = _mm256_max_ps(n, tmin);
    tmax = _mm256_min_ps(f, tmax);
  }
  widenSlabInterval8(tmin, tmax, Rows::nonNegativeTnear);
  _mm256_store_ps(entry, tmin);
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OS)));
}

struct Avx2NodeTest : Avx8LaneOps {
  /// The widening of the box intervals follows the tnear sign (widenSlabInterval8).
  static constexpr bool kReadsTnearSign = true;
  /// Eight-lane loads of the rays cost as much as keeping them: no per-walk state.
  explicit Avx2NodeTest(const PacketBoxRays&) {}
  template <class Rows>
  void test(const Bvh4Node& node, const PacketBoxRays& rays, unsigned lanes, unsigned hit[4],
            float entry[4][kPacketLanes]) const {
    const __m256 tnear = _mm256_load_ps(rays.tnear), tfar = _mm256_load_ps(rays.tfar);
    __m256 origin[3], reciprocal[3];
    for (int a = 0; a < 3; ++a) {
      origin[a] = _mm256_load_ps(rays.origin[a]);
      reciprocal[a] = _mm256_load_ps(rays.reciprocal[a]);
    }
    for (int s = 0; s < 4; ++s)
      hit[s] = slabTest8<Rows>(node, s, origin, reciprocal, tnear, tfar, entry[s]) & lanes;
  }
};

/// The pair walk's node test (PacketPairWalkImpl.h) with eight-lane registers: each slot against
/// one half, then the other, with Avx2NodeTest's arithmetic. The instructions per lane are those
/// of two packet walks; what the pair saves is the visits (node loads, ordering, stack) of the
/// nodes both halves enter, which pays for shadow packets only (PacketKernels::traversePair).
struct Avx2PairNodeTest {
  explicit Avx2PairNodeTest(PacketBoxRays* const (&)[2]) {}

  /// The lanes l of `mask` whose entry[l] lies beyond their tfar (ordered: false for NaN).
  static unsigned beyond(const float* entry, PacketBoxRays* const (&rays)[2], unsigned mask) {
    unsigned out = 0;
    for (unsigned h = 0; h < 2; ++h)
      out |= Avx8LaneOps::beyond(entry + kPacketLanes * h, rays[h]->tfar, kAllLanes)
             << (kPacketLanes * h);
    return out & mask;
  }

  static void copyEntry(const float* from, float* to) {
    _mm256_store_ps(to, _mm256_load_ps(from));
    _mm256_store_ps(to + kPacketLanes, _mm256_load_ps(from + kPacketLanes));
  }

  template <class Rows>
  void test(const Bvh4Node& node, PacketBoxRays* const (&rays)[2], unsigned lanes, unsigned hit[4],
            float entry[4][kPairLanes]) const {
    for (unsigned h = 0; h < 2; ++h) {
      const PacketBoxRays& half = *rays[h];
      const __m256 tnear = _mm256_load_ps(half.tnear), tfar = _mm256_load_ps(half.tfar);
      __m256 origin[3], reciprocal[3];
      for (int a = 0; a < 3; ++a) {
        origin[a] = _mm256_load_ps(half.origin[a]);
        reciprocal[a] = _mm256_load_ps(half.reciprocal[a]);
      }
      for (int s = 0; s < 4; ++s) {
        const unsigned mask =
            slabTest8<Rows>(node, s, origin, reciprocal, tnear, tfar, entry[s] + kPacketLanes * h);
        hit[s] = h == 0 ? mask : (hit[s] | (mask << kPacketLanes)) & lanes;
      }
    }
  }
};

}  // namespace

PacketKernels packetKernelsAvx2() {
  PacketKernels kernels = packetKernelsWith<Avx2NodeTest, Lanes8>(
      &loadBoxRaysAvx, &loadTransformedRowsAvx, &loadIdentityRowsAvx, &meetsOneBoxAvx);
  // Pairs for any hits only: with two registers per slot, the closest-hit pair walk measured no
  // faster than each packet alone (see PacketKernels::traversePair), shadow packets 5% faster.
  kernels.occludedPair = &occludedPair<Avx2PairNodeTest>;
  return kernels;
}

}  // namespace tg::detail
#else
namespace tg::detail {
PacketKernels packetKernelsAvx2() {
  return {};
}
}  // namespace tg::detail
#endif
