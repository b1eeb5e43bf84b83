// The inside step of the watertight triangle test for up to four triangles of a leaf at once
// (SSE, x86-64's baseline), on the leaf's vertices stored component by component (leaf rows).
// Internal header: not installed.
//
// A leaf of n triangles keeps its 9 * n floats as nine rows of n: row 3 * v + a holds component
// a of vertex v of each triangle, so one unaligned load gives that component of four triangles
// (lanes past n read the next rows or leaf, and are masked off). The edge functions are computed
// lane by lane with the operations of intersectWatertightWith, in the same order and without
// contraction, so every lane has the scalar test's bits; the rare candidates then finish one by
// one through finishWatertight, and lanes with an edge function exactly zero go to the scalar
// test whole, which decides them in double. The answers are therefore the scalar loop's.
#pragma once

#include <cstdint>

#include "Bvh4.h"
#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/WatertightTriangle.h"

namespace tg::detail {

/// Floats a leaf-row array needs past its last leaf: the widest load reads three lanes beyond
/// the last row of a one-triangle leaf.
inline constexpr std::size_t kLeafRowPadding = 4;

/// Most triangles a leaf with rows holds: one four-wide test takes them all (the SAH builder's
/// leaves hold at most BvhBuildOptions::maxLeafSize, 4).
inline constexpr std::uint32_t kMaxLeafRowsTriangles = 4;

/// Writes the `count` triangles at `triangles` as the rows of one leaf at `rows` (9 * count
/// floats).
inline void writeLeafRows(const TriangleVertices* triangles, std::uint32_t count, float* rows) {
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3f* v[3] = {&triangles[i].v0, &triangles[i].v1, &triangles[i].v2};
    for (int vertex = 0; vertex < 3; ++vertex)
      for (int axis = 0; axis < 3; ++axis)
        rows[(3 * vertex + axis) * count + i] = (*v[vertex])[axis];
  }
}

/// Triangle `lane` of the leaf of `count` triangles whose rows are at `rows`.
[[gnu::always_inline]] inline TriangleVertices readLeafRows(const float* rows, std::uint32_t count,
                                                            std::uint32_t lane) {
  const float* at = rows + lane;
  const auto vertex = [&](std::uint32_t v) {
    return Vec3f(at[(3 * v) * count], at[(3 * v + 1) * count], at[(3 * v + 2) * count]);
  };
  return {vertex(0), vertex(1), vertex(2)};
}

#if TG_BVH4_SSE

/// What the SIMD inside step found for the lanes of a leaf of up to four triangles.
struct LeafInside4 {
  /// Lanes that passed the inside test with no edge function zero: finishWatertight decides
  /// them, from the edge functions below.
  unsigned candidates = 0;
  /// Lanes with an edge function exactly zero in float: the scalar test decides them.
  unsigned exact = 0;
  ///@{
  /// Edge functions per lane; written only when `candidates` is not empty.
  alignas(16) float u[4], v[4], w[4];
  ///@}
};

/// The inside step for the triangles at `rows` (rows of a leaf whose row length is `stride`,
/// see writeLeafRows) in the lanes of `valid`, with the ray's axis permutation `axes`
/// (FixedAxes, see withFixedAxes).
template <class Axes>
[[gnu::always_inline]] inline void insideTest4(const WatertightRay& ray, const Axes& axes,
                                               const float* rows, std::uint32_t stride,
                                               unsigned valid, LeafInside4& out) {
  const auto row = [&](std::size_t vertex, std::size_t axis) {
    return _mm_loadu_ps(rows + (3 * vertex + axis) * stride);
  };
  const __m128 ox = _mm_set1_ps(ray.origin[axes.kx]);
  const __m128 oy = _mm_set1_ps(ray.origin[axes.ky]);
  const __m128 oz = _mm_set1_ps(ray.origin[axes.kz]);
  const __m128 sx = _mm_set1_ps(ray.sx), sy = _mm_set1_ps(ray.sy);
  // A = a - origin, then the shear: ax = A[kx] - sx * A[kz], as in intersectWatertightWith.
  const __m128 az = _mm_sub_ps(row(0, axes.kz), oz);
  const __m128 bz = _mm_sub_ps(row(1, axes.kz), oz);
  const __m128 cz = _mm_sub_ps(row(2, axes.kz), oz);
  const __m128 ax = _mm_sub_ps(_mm_sub_ps(row(0, axes.kx), ox), _mm_mul_ps(sx, az));
  const __m128 ay = _mm_sub_ps(_mm_sub_ps(row(0, axes.ky), oy), _mm_mul_ps(sy, az));
  const __m128 bx = _mm_sub_ps(_mm_sub_ps(row(1, axes.kx), ox), _mm_mul_ps(sx, bz));
  const __m128 by = _mm_sub_ps(_mm_sub_ps(row(1, axes.ky), oy), _mm_mul_ps(sy, bz));
  const __m128 cx = _mm_sub_ps(_mm_sub_ps(row(2, axes.kx), ox), _mm_mul_ps(sx, cz));
  const __m128 cy = _mm_sub_ps(_mm_sub_ps(row(2, axes.ky), oy), _mm_mul_ps(sy, cz));
  const __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  const __m128 v = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  const __m128 w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  const __m128 zero = _mm_setzero_ps();
  const unsigned exact =
      static_cast<unsigned>(_mm_movemask_ps(_mm_or_ps(
          _mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(v, zero)), _mm_cmpeq_ps(w, zero)))) &
      valid;
  // Outside when some edge function is negative and another positive (NaN is neither).
  const __m128 negative =
      _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)), _mm_cmplt_ps(w, zero));
  const __m128 positive =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)), _mm_cmpgt_ps(w, zero));
  const unsigned outside = static_cast<unsigned>(_mm_movemask_ps(_mm_and_ps(negative, positive)));
  out.exact = exact;
  out.candidates = valid & ~exact & ~outside;
  if (out.candidates == 0) return;
  _mm_store_ps(out.u, u);
  _mm_store_ps(out.v, v);
  _mm_store_ps(out.w, w);
}

/// The leaf test of one ray against the leaf of `count` triangles (at most four) at `rows`:
/// calls onHit(lane, hit) in lane order, which is triangle order, for each triangle the ray hits
/// in [ray.tnear, tfar], until onHit returns true; returns that lane, or -1. `tfar` is read again
/// for every triangle, as the scalar loop reads ray.tfar, so onHit may lower it.
template <class Axes, class OnHit>
[[gnu::always_inline]] inline int forEachLeafRowsHit(const WatertightRay& ray, const Axes& axes,
                                                     const float* rows, std::uint32_t count,
                                                     const float& tfar, const OnHit& onHit) {
  LeafInside4 inside;
  insideTest4(ray, axes, rows, count, (1u << count) - 1u, inside);
  for (unsigned m = inside.candidates | inside.exact; m != 0; m &= m - 1) {
    const auto lane = static_cast<unsigned>(__builtin_ctz(m));
    const TriangleVertices tri = readLeafRows(rows, count, lane);
    TriangleHit hit;
    const bool found = inside.exact & (1u << lane)
                           ? intersectWatertightWith(ray, axes, tri.v0, tri.v1, tri.v2, tfar, hit)
                           : finishWatertight(ray, tri.v0, tri.v1, tri.v2, inside.u[lane],
                                              inside.v[lane], inside.w[lane], tfar, hit);
    if (found && onHit(lane, hit)) return static_cast<int>(lane);
  }
  return -1;
}

#endif  // TG_BVH4_SSE

}  // namespace tg::detail
