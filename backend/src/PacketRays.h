// Filling a PacketBoxRays from rays, on the baseline side of the packet kernels. Internal
// header: not installed, and never included by the kernel translation units.
#pragma once

#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "PacketKernel.h"
#include "tracegraph/backend/Vec3.h"

namespace tg::detail {

/// Number of lanes set in a packet mask. __builtin_popcount is a library call on the x86-64
/// baseline (no POPCNT instruction), and a mask is only kPacketLanes bits.
inline int laneCount(unsigned lanes) {
  static_assert(kPacketLanes == 8, "laneCount counts two nibbles");
  static constexpr unsigned char kNibbleBits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  return kNibbleBits[lanes & 15u] + kNibbleBits[(lanes >> 4) & 15u];
}

/// Bit a set when direction[a] < 0. Zero components (+0 and -0) count as positive, as in
/// Bvh4Ray, whose reciprocal of a zero is +inf.
inline unsigned directionSigns(const Vec3f& direction) {
  return (direction.x < 0.0f ? 1u : 0u) | (direction.y < 0.0f ? 2u : 0u) |
         (direction.z < 0.0f ? 4u : 0u);
}

/// Writes lane `lane` with the per-ray constants Bvh4Ray computes for the same ray, from its
/// reciprocal direction (1/d per component, +-inf for +-0, as ObjectRay::inverseDirection holds
/// it): a zero component's reciprocal becomes +inf whatever its sign.
inline void setPacketLaneWithReciprocal(PacketBoxRays& rays, unsigned lane, const Vec3f& origin,
                                        const Vec3f& direction, const Vec3f& reciprocal,
                                        float tnear, float tfar) {
  for (int a = 0; a < 3; ++a) {
    rays.origin[a][lane] = origin[a];
    rays.reciprocal[a][lane] =
        direction[a] == 0.0f ? std::numeric_limits<float>::infinity() : reciprocal[a];
  }
  rays.tnear[lane] = tnear;
  rays.tfar[lane] = tfar;
}

/// setPacketLaneWithReciprocal for a ray whose reciprocal is not known yet: leaves the lane's
/// direction where its reciprocal goes; after every lane and fillUnusedLanes,
/// setPacketReciprocals turns all of them into reciprocals at once.
inline void setPacketLaneDirection(PacketBoxRays& rays, unsigned lane, const Vec3f& origin,
                                   const Vec3f& direction, float tnear, float tfar) {
  for (int a = 0; a < 3; ++a) {
    rays.origin[a][lane] = origin[a];
    rays.reciprocal[a][lane] = direction[a];
  }
  rays.tnear[lane] = tnear;
  rays.tfar[lane] = tfar;
}

/// Replaces the directions that setPacketLaneDirection left in rays.reciprocal by Bvh4Ray's
/// reciprocals (1/d, +inf for +-0), four lanes per division where SSE is available:
/// a correctly rounded quotient is the same whether computed alone or in a vector.
inline void setPacketReciprocals(PacketBoxRays& rays) {
#if defined(__SSE2__)
  const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  for (int a = 0; a < 3; ++a)
    for (unsigned h = 0; h < kPacketLanes; h += 4) {
      const __m128 d = _mm_load_ps(rays.reciprocal[a] + h);
      const __m128 isZero = _mm_cmpeq_ps(d, zero);
      const __m128 r = _mm_div_ps(one, d);
      _mm_store_ps(rays.reciprocal[a] + h,
                   _mm_or_ps(_mm_and_ps(isZero, inf), _mm_andnot_ps(isZero, r)));
    }
#else
  for (int a = 0; a < 3; ++a)
    for (unsigned l = 0; l < kPacketLanes; ++l) {
      const float d = rays.reciprocal[a][l];
      rays.reciprocal[a][l] = d == 0.0f ? std::numeric_limits<float>::infinity() : 1.0f / d;
    }
#endif
}

/// Sets the shared plane rows for direction signs `signs` (see directionSigns).
inline void setPacketRows(PacketBoxRays& rays, unsigned signs) {
  for (int a = 0; a < 3; ++a) {
    const bool negative = (signs >> a) & 1u;
    rays.nearRow[a] = 2 * a + (negative ? 1 : 0);
    rays.farRow[a] = 2 * a + (negative ? 0 : 1);
  }
}

/// Copies lane `from` into every lane outside `lanes`, so that the kernel's full-width
/// arithmetic on unused lanes sees ordinary numbers (their results are masked off).
inline void fillUnusedLanes(PacketBoxRays& rays, unsigned lanes, unsigned from) {
  for (unsigned l = 0; l < kPacketLanes; ++l) {
    if (lanes & (1u << l)) continue;
    for (int a = 0; a < 3; ++a) {
      rays.origin[a][l] = rays.origin[a][from];
      rays.reciprocal[a][l] = rays.reciprocal[a][from];
    }
    rays.tnear[l] = rays.tnear[from];
    rays.tfar[l] = rays.tfar[from];
  }
}

/// Packets with fewer coherent lanes than this are traced as single rays: the shared walk
/// costs more than it saves for one or two rays.
inline constexpr int kMinPacketLanes = 3;

}  // namespace tg::detail
