// The watertight triangle test over the lanes of a packet, written once for any SIMD width: each
// kernel translation unit instantiates it with its vector types. Internal linkage only (see
// PacketKernel.h). Internal header: not installed.
//
// V (floats) must provide: V::kWidth lanes; V::load(const float*), V::broadcast(float),
// v.store(float*); +, -, *, /; and the lane masks V::anyZero(U, V, W) (some edge function is
// zero), V::inside(U, V, W) (no two edge functions of opposite sign, and U + V + W not zero,
// NaN counting as not zero), V::select(bits, a, b) (a in the lanes of `bits`, b elsewhere) and
// V::inRange(t, tnear, tfar) (tnear <= t <= tfar and t finite, false for NaN). V::Doubles (the
// same lanes in double) must provide load, broadcast, +, -, *, /, D::nonZero(x) (x != 0, NaN
// counting as not zero) and V::fromDoubles(D) (rounding to float).
// Plain operators keep the scalar test's order of operations; the kernels are compiled without
// floating-point contraction, so every lane rounds exactly as intersectWatertight does.
#pragma once

#include <cstring>

#include "PacketKernel.h"

namespace tg::detail {
namespace {

/// testTrianglesWith for a component stride of kStride floats, or of vertices.componentStride
/// when kStride is 0.
template <class V, std::size_t kStride, unsigned kLanes>
std::uint32_t testTrianglesStrided(const TriangleFloats& vertices, std::uint32_t count,
                                   const TriangleRaysOf<kLanes>& rays, const float* tfarIn,
                                   unsigned lanes, bool anyHit, TriangleHitsOf<kLanes>& out) {
  using D = typename V::Doubles;
  constexpr unsigned kWidthMask = (1u << V::kWidth) - 1u;
  const int kx = rays.kx, ky = rays.ky, kz = rays.kz;
  // tfar is written and read in whole vectors only: a vector load of lanes just stored one by
  // one cannot be forwarded from the store buffer and waits for the stores to retire.
  alignas(64) float tfar[kLanes];
  std::memcpy(tfar, tfarIn, sizeof(tfar));
  unsigned live = lanes;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float* at = vertices.at + vertices.triangleStride * i;
    const std::size_t stride = kStride != 0 ? kStride : vertices.componentStride;
    // Component a of vertex v: tri(3 * v + a).
    const auto tri = [&](int component) {
      return at[static_cast<std::size_t>(component) * stride];
    };
    // The plane of the triangle in double, as intersectWatertight computes it per ray: the
    // same for every lane, so computed once.
    const double a[3] = {tri(0), tri(1), tri(2)};
    const double e1[3] = {double(tri(3)) - a[0], double(tri(4)) - a[1], double(tri(5)) - a[2]};
    const double e2[3] = {double(tri(6)) - a[0], double(tri(7)) - a[1], double(tri(8)) - a[2]};
    double* n = out.normal[i];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    unsigned hitMask = 0, exactMask = 0;
    for (unsigned h = 0; h < kLanes; h += V::kWidth) {
      const unsigned sub = (live >> h) & kWidthMask;
      if (sub == 0) continue;
      const V ox = V::load(rays.origin[kx] + h), oy = V::load(rays.origin[ky] + h),
              oz = V::load(rays.origin[kz] + h);
      const V sx = V::load(rays.sx + h), sy = V::load(rays.sy + h);
      // A = a - origin, then the shear: ax = A[kx] - sx * A[kz], as in intersectWatertight.
      const V az = V::broadcast(tri(kz)) - oz, bz = V::broadcast(tri(3 + kz)) - oz,
              cz = V::broadcast(tri(6 + kz)) - oz;
      const V ax = (V::broadcast(tri(kx)) - ox) - sx * az;
      const V ay = (V::broadcast(tri(ky)) - oy) - sy * az;
      const V bx = (V::broadcast(tri(3 + kx)) - ox) - sx * bz;
      const V by = (V::broadcast(tri(3 + ky)) - oy) - sy * bz;
      const V cx = (V::broadcast(tri(6 + kx)) - ox) - sx * cz;
      const V cy = (V::broadcast(tri(6 + ky)) - oy) - sy * cz;
      const V u = cx * by - cy * bx;
      const V v = ax * cy - ay * cx;
      const V w = bx * ay - by * ax;
      const unsigned exact = V::anyZero(u, v, w) & sub;
      exactMask |= exact << h;
      const unsigned inside = V::inside(u, v, w) & sub & ~exact;
      if (inside == 0) continue;
      // t = n.(a - o) / n.d on the double ray, the scalar test's refinement.
      const D dx = D::load(rays.directionD[0] + h), dy = D::load(rays.directionD[1] + h),
              dz = D::load(rays.directionD[2] + h);
      const D nx = D::broadcast(n[0]), ny = D::broadcast(n[1]), nz = D::broadcast(n[2]);
      const D nd = nx * dx + ny * dy + nz * dz;
      const D qx = D::broadcast(a[0]) - D::load(rays.originD[0] + h);
      const D qy = D::broadcast(a[1]) - D::load(rays.originD[1] + h);
      const D qz = D::broadcast(a[2]) - D::load(rays.originD[2] + h);
      const V t = V::fromDoubles((nx * qx + ny * qy + nz * qz) / nd);
      const unsigned hit =
          inside & D::nonZero(nd) & V::inRange(t, V::load(rays.tnear + h), V::load(tfar + h));
      if (hit == 0) continue;
      const V invDet = V::broadcast(1.0f) / ((u + v) + w);
      // A closer hit shortens the lane for the triangles after, as ray.tfar does in the scalar
      // leaf loop.
      V::select(hit, t, V::load(tfar + h)).store(tfar + h);
      t.store(out.t[i] + h);
      (v * invDet).store(out.u[i] + h);
      (w * invDet).store(out.v[i] + h);
      hitMask |= hit << h;
    }
    out.hit[i] = hitMask;
    out.exact[i] = exactMask;
    // An any-hit lane is done.
    if (anyHit) live &= ~hitMask;
    if (exactMask != 0 || live == 0) return i + 1;
  }
  return count;
}

template <class V, unsigned kLanes = kPacketLanes>
std::uint32_t testTrianglesWith(const TriangleFloats& vertices, std::uint32_t count,
                                const TriangleRaysOf<kLanes>& rays, const float* tfarIn,
                                unsigned lanes, bool anyHit, TriangleHitsOf<kLanes>& out) {
  // The strides of packed triangles and of leaf rows (a leaf's size, at most four) as
  // constants: the vertex reads then take constant offsets, where a stride known only at run
  // time cost the kernel a fifth more instructions (BART kitchen packets).
  switch (vertices.componentStride) {
    case 1:
      return testTrianglesStrided<V, 1, kLanes>(vertices, count, rays, tfarIn, lanes, anyHit, out);
    case 2:
      return testTrianglesStrided<V, 2, kLanes>(vertices, count, rays, tfarIn, lanes, anyHit, out);
    case 3:
      return testTrianglesStrided<V, 3, kLanes>(vertices, count, rays, tfarIn, lanes, anyHit, out);
    case 4:
      return testTrianglesStrided<V, 4, kLanes>(vertices, count, rays, tfarIn, lanes, anyHit, out);
    default:
      return testTrianglesStrided<V, 0, kLanes>(vertices, count, rays, tfarIn, lanes, anyHit, out);
  }
}

/// The closest-hit triangle test of a pair's lanes (PairTriangleTestFn).
template <class V>
std::uint32_t testTrianglesPairWith(const TriangleFloats& vertices, std::uint32_t count,
                                    const PairTriangleRays& rays, const float* tfar, unsigned lanes,
                                    PairTriangleHits& out) {
  return testTrianglesWith<V, kPairLanes>(vertices, count, rays, tfar, lanes, false, out);
}

}  // namespace
}  // namespace tg::detail
