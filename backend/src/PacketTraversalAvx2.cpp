// The AVX2 packet kernel: one instruction tests a child box against all eight lanes. Compiled
// with -mavx2 -mfma -ffp-contract=off (see backend/CMakeLists.txt): contraction would fuse the
// slab products into FMAs and round differently from the single-ray test.
#include "PacketKernel.h"

#if defined(__AVX2__)
#include <immintrin.h>

#include "PacketLanesAvx.h"
#include "PacketObjectRowsAvx.h"
#include "PacketOneBox8.h"
#include "PacketTraversalImpl.h"
#include "SlabWidening8.h"

namespace tg::detail {
namespace {

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
    for (int s = 0; s < 4; ++s) {
      __m256 tmin = tnear, tmax = tfar;
      for (int a = 0; a < 3; ++a) {
        const __m256 n = _mm256_mul_ps(
            _mm256_sub_ps(_mm256_set1_ps(node.bounds[Rows::nearRow(a)][s]), origin[a]),
            reciprocal[a]);
        const __m256 f =
            _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(node.bounds[Rows::farRow(a)][s]), origin[a]),
                          reciprocal[a]);
        tmin = _mm256_max_ps(n, tmin);
        tmax = _mm256_min_ps(f, tmax);
      }
      widenSlabInterval8(tmin, tmax, Rows::nonNegativeTnear);
      _mm256_store_ps(entry[s], tmin);
      hit[s] =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OS))) & lanes;
    }
  }
};

}  // namespace

PacketKernels packetKernelsAvx2() {
  return packetKernelsWith<Avx2NodeTest, Lanes8>(&loadBoxRaysAvx, &loadTransformedRowsAvx,
                                                 &loadIdentityRowsAvx, &meetsOneBoxAvx);
}

}  // namespace tg::detail
#else
namespace tg::detail {
PacketKernels packetKernelsAvx2() {
  return {};
}
}  // namespace tg::detail
#endif
