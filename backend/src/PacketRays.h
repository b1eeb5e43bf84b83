// Filling a PacketBoxRays from rays, on the baseline side of the packet kernels. Internal
// header: not installed, and never included by the kernel translation units.
#pragma once

#include <algorithm>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "PacketKernel.h"
#include "tracegraph/backend/Ray.h"
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

/// Replaces directions held in rays.reciprocal (every lane, unused ones filled) by Bvh4Ray's
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

/// Copies lane `from` into every lane outside `lanes`, so that the kernel's full-width
/// arithmetic on unused lanes sees ordinary numbers (their results are masked off).
inline void fillUnusedLanes(PacketBoxRays& rays, unsigned lanes, unsigned from) {
  static_assert(sizeof(PacketBoxRays::origin) + sizeof(PacketBoxRays::reciprocal) +
                        sizeof(PacketBoxRays::tnear) + sizeof(PacketBoxRays::tfar) ==
                    8 * kPacketLanes * sizeof(float),
                "the box rays begin with eight rows of lanes");
  if (lanes == kAllLanes) return;
  // The eight rows are contiguous: one blend per half row, instead of a branch per lane and row.
  float* rows = rays.origin[0];
#if defined(__SSE2__)
  static_assert(kPacketLanes == 8, "two halves of four lanes");
  const __m128i bits = _mm_setr_epi32(1, 2, 4, 8);
  const __m128i word = _mm_set1_epi32(static_cast<int>(lanes));
  const __m128 keep[2] = {
      _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(word, bits), bits)),
      _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_srli_epi32(word, 4), bits), bits))};
  for (unsigned r = 0; r < 8; ++r) {
    float* row = rows + r * kPacketLanes;
    const __m128 lead = _mm_set1_ps(row[from]);
    for (unsigned h = 0; h < 2; ++h) {
      const __m128 v = _mm_load_ps(row + 4 * h);
      _mm_store_ps(row + 4 * h, _mm_or_ps(_mm_and_ps(keep[h], v), _mm_andnot_ps(keep[h], lead)));
    }
  }
#else
  for (unsigned r = 0; r < 8; ++r) {
    float* row = rows + r * kPacketLanes;
    for (unsigned l = 0; l < kPacketLanes; ++l)
      if (!(lanes & (1u << l))) row[l] = row[from];
  }
#endif
}

/// Rays rays[0..kPacketLanes) as rows of lanes: row r holds float r of every ray, in Ray's
/// member order (origin x, y, z, tnear, direction x, y, z, tfar).
struct alignas(16) PacketRayRows {
  /// Row per Ray member float, lane per ray.
  float row[8][kPacketLanes];
};

/// Writes float r of every ray of rays[0..kPacketLanes) (all of them are read) into row[r], a
/// 16-byte aligned row of kPacketLanes floats, in Ray's member order. A transpose of 4 x 4
/// blocks where SSE is available: the per-lane copies it replaces were a large share of a
/// packet's set-up.
inline void loadRayRows(const Ray* rays, float* const (&row)[8]) {
  static_assert(sizeof(Ray) == 8 * sizeof(float), "a ray is eight packed floats");
  const auto* f = reinterpret_cast<const float*>(rays);
#if defined(__SSE2__)
  static_assert(kPacketLanes == 8, "two blocks of four lanes");
  for (unsigned h = 0; h < kPacketLanes; h += 4)
    for (unsigned q = 0; q < 8; q += 4) {
      __m128 r0 = _mm_loadu_ps(f + 8 * h + q), r1 = _mm_loadu_ps(f + 8 * (h + 1) + q);
      __m128 r2 = _mm_loadu_ps(f + 8 * (h + 2) + q), r3 = _mm_loadu_ps(f + 8 * (h + 3) + q);
      _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
      _mm_store_ps(row[q] + h, r0);
      _mm_store_ps(row[q + 1] + h, r1);
      _mm_store_ps(row[q + 2] + h, r2);
      _mm_store_ps(row[q + 3] + h, r3);
    }
#else
  for (unsigned l = 0; l < kPacketLanes; ++l)
    for (unsigned r = 0; r < 8; ++r) row[r][l] = f[8 * l + r];
#endif
}

/// loadRayRows into `out`.
inline void loadRayRows(const Ray* rays, PacketRayRows& out) {
  float* const row[8] = {out.row[0], out.row[1], out.row[2], out.row[3],
                         out.row[4], out.row[5], out.row[6], out.row[7]};
  loadRayRows(rays, row);
}

/// The lanes l for which isTraceable(rays[l]) holds, from the rays' rows (loadRayRows, before
/// anything is written into them): checking the rows costs a fraction of checking lane by lane.
inline unsigned traceableLanes(const float* const (&row)[8]) {
#if defined(__SSE2__)
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 inf = _mm_set1_ps(kInfinity), zero = _mm_setzero_ps();
  unsigned lanes = 0;
  for (unsigned h = 0; h < kPacketLanes; h += 4) {
    const auto load = [&](int r) { return _mm_load_ps(row[r] + h); };
    // |x| < inf: false for infinities and NaN, as !isfinite.
    __m128 ok = _mm_cmplt_ps(_mm_and_ps(load(0), absMask), inf);
    for (int r : {1, 2, 4, 5, 6})
      ok = _mm_and_ps(ok, _mm_cmplt_ps(_mm_and_ps(load(r), absMask), inf));
    const __m128 nonZero =
        _mm_or_ps(_mm_or_ps(_mm_cmpneq_ps(load(4), zero), _mm_cmpneq_ps(load(5), zero)),
                  _mm_cmpneq_ps(load(6), zero));
    // tnear <= tfar is false when either is NaN.
    ok = _mm_and_ps(_mm_and_ps(ok, nonZero), _mm_cmple_ps(load(3), load(7)));
    lanes |= static_cast<unsigned>(_mm_movemask_ps(ok)) << h;
  }
  return lanes;
#else
  unsigned lanes = 0;
  for (unsigned l = 0; l < kPacketLanes; ++l) {
    Ray r;
    r.origin = {row[0][l], row[1][l], row[2][l]};
    r.tnear = row[3][l];
    r.direction = {row[4][l], row[5][l], row[6][l]};
    r.tfar = row[7][l];
    lanes |= (isTraceable(r) ? 1u : 0u) << l;
  }
  return lanes;
#endif
}

/// Lowers tfar[l] to hits[l].t for every lane (std::min(tfar[l], hits[l].t), bit for bit).
inline void lowerToHits(float* tfar, const Hit* hits) {
  alignas(16) float t[kPacketLanes];
  for (unsigned l = 0; l < kPacketLanes; ++l) t[l] = hits[l].t;
#if defined(__SSE2__)
  // MINPS(a, b) is a < b ? a : b, which is std::min(b, a).
  for (unsigned h = 0; h < kPacketLanes; h += 4)
    _mm_store_ps(tfar + h, _mm_min_ps(_mm_load_ps(t + h), _mm_load_ps(tfar + h)));
#else
  for (unsigned l = 0; l < kPacketLanes; ++l) tfar[l] = std::min(tfar[l], t[l]);
#endif
}

/// The lanes whose row value is < 0 (not -0, not NaN), as directionSigns tests a component.
inline unsigned negativeLanes(const float* row) {
#if defined(__SSE2__)
  const __m128 zero = _mm_setzero_ps();
  return static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(row), zero))) |
         static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(row + 4), zero))) << 4;
#else
  unsigned out = 0;
  for (unsigned l = 0; l < kPacketLanes; ++l) out |= (row[l] < 0.0f ? 1u : 0u) << l;
  return out;
#endif
}

/// The portable BoxRayLoadFn (SSE where available).
inline unsigned loadPacketBoxRays(const Ray* rays, const Hit* hits, unsigned& lanes,
                                  PacketBoxRays& out) {
  // All eight rays straight into their rows, directions where the reciprocals go
  // (setPacketReciprocals divides them). Lanes outside `coherent` get the first lane's values.
  float* const rows[8] = {out.origin[0],     out.origin[1],     out.origin[2],     out.tnear,
                          out.reciprocal[0], out.reciprocal[1], out.reciprocal[2], out.tfar};
  loadRayRows(rays, rows);
  lanes &= traceableLanes(rows);
  if (lanes == 0) return 0;
  const unsigned firstLane = static_cast<unsigned>(__builtin_ctz(lanes));
  unsigned coherent = lanes, signs = 0;
  for (int a = 0; a < 3; ++a) {
    const unsigned negative = negativeLanes(out.reciprocal[a]);
    const bool leadNegative = (negative >> firstLane) & 1u;
    signs |= (leadNegative ? 1u : 0u) << a;
    coherent &= leadNegative ? negative : ~negative;
  }
  if (hits) lowerToHits(out.tfar, hits);
  out.signs = signs;
  fillUnusedLanes(out, coherent, firstLane);
  setPacketReciprocals(out);
  return coherent;
}

/// Packets with fewer coherent lanes than this are traced as single rays: the shared walk
/// costs more than it saves for one or two rays.
inline constexpr int kMinPacketLanes = 3;

}  // namespace tg::detail
