// SSE binning for the binned-SAH builder: one pass puts every primitive's box into a bin of each
// of the three axes at once, and one sweep per axis finds the cheapest plane. Only SSE2 is used,
// which every x86-64 processor has, so this needs no run-time ISA choice.
// Internal header: not installed.
#pragma once

#include <emmintrin.h>

#include <cstdint>
#include <limits>

#include "BvhBuilder.h"

namespace tg::detail {

/// dx * dy + dy * dz + dz * dx of the box [lo, hi] in lanes 0-2, summed in the order of
/// Box3f::area and without a round trip through memory (the sweep takes two per bin and axis).
inline float halfArea(__m128 lo, __m128 hi) {
  const __m128 d = _mm_sub_ps(hi, lo);
  const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));
  const __m128 s = _mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1)));
  return _mm_cvtss_f32(_mm_add_ss(s, _mm_movehl_ps(p, p)));
}

/// A box in two SSE registers (lane 3 unused).
struct SseBox {
  /// Minimum corner in lanes 0-2.
  __m128 lower = _mm_set1_ps(std::numeric_limits<float>::infinity());
  /// Maximum corner in lanes 0-2.
  __m128 upper = _mm_set1_ps(-std::numeric_limits<float>::infinity());

  /// The box `b` (lane 3 zero).
  static SseBox of(const Box3f& b) {
    return {_mm_setr_ps(b.lower.x, b.lower.y, b.lower.z, 0.0f),
            _mm_setr_ps(b.upper.x, b.upper.y, b.upper.z, 0.0f)};
  }
  /// Grows the box to contain [lo, hi].
  void extend(__m128 lo, __m128 hi) {
    lower = _mm_min_ps(lower, lo);
    upper = _mm_max_ps(upper, hi);
  }
  /// Grows the box to contain `b`.
  void extend(const SseBox& b) { extend(b.lower, b.upper); }
  /// The box as a Box3f.
  Box3f box() const {
    alignas(16) float lo[4], hi[4];
    _mm_store_ps(lo, lower);
    _mm_store_ps(hi, upper);
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  }
  /// Surface area, as Box3f::area() computes it (0 when empty).
  float area() const {
    if ((_mm_movemask_ps(_mm_cmplt_ps(upper, lower)) & 7) != 0) return 0.0f;
    return 2.0f * halfArea(lower, upper);
  }
  /// Surface area of a box known not to be empty.
  float nonEmptyArea() const { return 2.0f * halfArea(lower, upper); }
};

/// Loads a primitive's box corners with lane 3 cleared. In memory lane 3 of the lower corner
/// holds the id, whose bits read as a denormal float: arithmetic on it (the centroid sums of
/// binning and partitioning) would take a microcode assist on every primitive, which made
/// binning about three times slower. The upper corner's lane 3 is the zero padding.
inline __m128 primLower(const BvhPrim& p) {
  const __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  return _mm_and_ps(_mm_load_ps(p.lower), xyz);
}
inline __m128 primUpper(const BvhPrim& p) {
  return _mm_load_ps(p.upper);
}

/// Maps centroids (stored as lower + upper) to bins on all three axes with one multiply. The
/// float clamp before the conversion keeps it defined for any input: a NaN or an overflowing
/// product lands in bin 0 or the last bin. The scalar binOf gives bit-identical answers, so the
/// partition agrees with the binning.
struct BinMapping {
  /// Centroid coordinate of bin 0 per axis.
  __m128 origin;
  /// Bins per unit of centroid coordinate per axis (0 on an axis that is not binned).
  __m128 scale;
  /// Index of the last bin, as a float.
  __m128 last;

  /// Bins of the centroid lo + hi on each axis.
  __m128i bins(__m128 lo, __m128 hi) const {
    __m128 f = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(lo, hi), origin), scale);
    // max(f, 0) returns 0 for NaN (the second operand), as the scalar f > 0 ? f : 0.
    f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), last);
    return _mm_cvttps_epi32(f);
  }
};

/// Scalar bin of one centroid coordinate, for the binning along one axis: the same operations
/// as BinMapping::bins on one lane, so both give the same bins (and the clamps do not branch).
inline int binOf(float c, float origin, float scale, int bins) {
  __m128 f = _mm_mul_ss(_mm_sub_ss(_mm_set_ss(c), _mm_set_ss(origin)), _mm_set_ss(scale));
  f = _mm_max_ss(f, _mm_setzero_ps());
  f = _mm_min_ss(f, _mm_set_ss(static_cast<float>(bins - 1)));
  return _mm_cvttss_si32(f);
}

/// Swaps two primitives as two 16-byte halves each. A member-wise swap stores them in pieces,
/// and a partition that reloads a slot it has just written then waits for store forwarding
/// to fail on every such pair.
inline void swapPrims(BvhPrim& a, BvhPrim& b) {
  const __m128 aLo = _mm_load_ps(a.lower), aHi = _mm_load_ps(a.upper);
  const __m128 bLo = _mm_load_ps(b.lower), bHi = _mm_load_ps(b.upper);
  _mm_store_ps(a.lower, bLo);
  _mm_store_ps(a.upper, bHi);
  _mm_store_ps(b.lower, aLo);
  _mm_store_ps(b.upper, aHi);
}

/// Bin boxes and counts of one range on the three axes. Only the first `used` bins are
/// initialised: most ranges are small and use a few bins.
struct BinSet {
  /// Bin box corners (lane 3 unused), left uninitialised until reset.
  struct Bin {
    __m128 lower, upper;
  };
  Bin box[3][BvhBuildOptions::kMaxBins];
  std::uint32_t count[3][BvhBuildOptions::kMaxBins];
  int used = 0;

  /// Empties the first `bins` bins of every axis.
  void reset(int bins) {
    used = bins;
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    const __m128 negInf = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < bins; ++b) {
        box[a][b] = {inf, negInf};
        count[a][b] = 0;
      }
  }

  /// Bins prims[begin, end) on all three axes.
  void add(const BvhPrim* prims, std::size_t begin, std::size_t end, const BinMapping& map) {
    for (std::size_t i = begin; i < end; ++i) addOne(prims[i], map);
  }

  /// Bins prims[begin, end) on all three axes, alternating between this set and `odd` (reset
  /// to the same bin count), which the caller merges afterwards. Neighbouring primitives of a
  /// mesh often fall into the same bin, and then every update waits for the previous one's
  /// store; alternating gives each chain a primitive of slack.
  void addInterleaved(const BvhPrim* prims, std::size_t begin, std::size_t end,
                      const BinMapping& map, BinSet& odd) {
    std::size_t i = begin;
    for (; i + 1 < end; i += 2) {
      addOne(prims[i], map);
      odd.addOne(prims[i + 1], map);
    }
    if (i < end) addOne(prims[i], map);
  }

  /// Bins one primitive on all three axes.
  void addOne(const BvhPrim& p, const BinMapping& map) {
    const __m128 lo = primLower(p), hi = primUpper(p);
    // Lanes moved to general registers directly: a store and three reloads cost more here.
    const __m128i b = map.bins(lo, hi);
    addTo(0, _mm_cvtsi128_si32(b), lo, hi);
    addTo(1, _mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0x55)), lo, hi);
    addTo(2, _mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0xAA)), lo, hi);
  }

  /// Bins prims[begin, end) on `axis` only, whose mapping is `origin` and `scale` (the
  /// scalar binOf gives the same bins as BinMapping).
  void addOnAxis(const BvhPrim* prims, std::size_t begin, std::size_t end, int axis, float origin,
                 float scale) {
    for (std::size_t i = begin; i < end; ++i) {
      const BvhPrim& p = prims[i];
      const int b = binOf(p.lower[axis] + p.upper[axis], origin, scale, used);
      addTo(axis, b, primLower(p), primUpper(p));
    }
  }

  /// Grows bin `b` of `axis` by the box [lo, hi].
  void addTo(int axis, int b, __m128 lo, __m128 hi) {
    Bin& x = box[axis][b];
    x.lower = _mm_min_ps(x.lower, lo);
    x.upper = _mm_max_ps(x.upper, hi);
    ++count[axis][b];
  }

  /// Adds the bins of `o` (same bin count).
  void merge(const BinSet& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < used; ++b) {
        box[a][b].lower = _mm_min_ps(box[a][b].lower, o.box[a][b].lower);
        box[a][b].upper = _mm_max_ps(box[a][b].upper, o.box[a][b].upper);
        count[a][b] += o.count[a][b];
      }
  }
};

/// The cheapest binned plane of one range.
struct BinSplit {
  /// Axis, or -1 when no plane separates two non-empty sides.
  int axis = -1;
  /// Primitives in bins [0, bin) go left.
  int bin = 0;
  /// area(left) * |left| + area(right) * |right|.
  float cost = std::numeric_limits<float>::infinity();
};

/// Sweeps the axes whose `active` flag is set (bits 0-2) and returns the cheapest plane; ties go
/// to the lower axis, then the lower bin, so the answer depends on the bins alone.
inline BinSplit sweepBins(const BinSet& bins, unsigned active) {
  BinSplit best;
  const int n = bins.used;
  for (int a = 0; a < 3; ++a) {
    if ((active & (1u << a)) == 0) continue;
    float rightCost[BvhBuildOptions::kMaxBins];  // written for bins [1, n) below
    SseBox acc;
    std::uint32_t count = 0;
    for (int b = n - 1; b > 0; --b) {
      acc.extend(bins.box[a][b].lower, bins.box[a][b].upper);
      count += bins.count[a][b];
      rightCost[b] = count == 0 ? -1.0f : acc.nonEmptyArea() * static_cast<float>(count);
    }
    acc = SseBox{};
    count = 0;
    for (int b = 1; b < n; ++b) {
      acc.extend(bins.box[a][b - 1].lower, bins.box[a][b - 1].upper);
      count += bins.count[a][b - 1];
      if (count == 0 || rightCost[b] < 0.0f) continue;
      const float cost = acc.nonEmptyArea() * static_cast<float>(count) + rightCost[b];
      if (cost < best.cost) {
        best.cost = cost;
        best.axis = a;
        best.bin = b;
      }
    }
  }
  return best;
}

}  // namespace tg::detail
