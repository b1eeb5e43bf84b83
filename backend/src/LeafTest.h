// The leaf step every object accelerator shares: one watertight triangle test and the tie rule.
// Internal header: not installed.
#pragma once

#include <algorithm>
#include <cmath>

#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/ObjectAccel.h"

namespace tg::detail {

/// The object-space geometric normal of a hit as the float that Hit::geometricNormal carries
/// until Scene maps it to world space. The double cross product of a tiny triangle can lie below
/// float's range (edges of 1e-20 give 1e-40); it is then scaled by a power of two, which keeps
/// its direction exactly. Its length does not matter: Scene normalises after the mapping.
inline Vec3f objectNormalForHit(const Vec3d& n) {
  const double m = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  if (m > 0x1p-100 && m < 0x1p100) return Vec3f(n);
  int exponent = 0;
  std::frexp(m, &exponent);
  return Vec3f(n * std::ldexp(1.0, -exponent));
}

/// Records the triangle hit `th` of mesh triangle `prim` in `hit` when it precedes it
/// (hitPrecedes), and lowers ray.tfar to its t. `th` must lie in [tnear, ray.tfar].
inline bool recordHit(ObjectRay& ray, const TriangleHit& th, std::uint32_t prim, Hit& hit) {
  if (!hitPrecedes(th.t, ray.instanceId, prim, hit)) return false;
  hit.t = th.t;
  hit.u = th.u;
  hit.v = th.v;
  hit.primId = prim;
  hit.instanceId = ray.instanceId;
  hit.objectId = ray.objectId;
  hit.geometricNormal = objectNormalForHit(th.normal);
  ray.tfar = th.t;
  return true;
}

/// recordTriangleHit with the ray's axis permutation given as `axes` (see withFixedAxes).
template <class Axes>
inline bool recordTriangleHitWith(ObjectRay& ray, const Axes& axes, const TriangleVertices& tri,
                                  std::uint32_t prim, Hit& hit) {
  TriangleHit th;
  if (!intersectWatertightWith(ray.wt, axes, tri.v0, tri.v1, tri.v2, ray.tfar, th)) return false;
  return recordHit(ray, th, prim, hit);
}

/// True when `tri` is hit by `ray` for t in [tnear, ray.tfar] (the any-hit step), with the
/// ray's axis permutation given as `axes` (see withFixedAxes).
template <class Axes>
inline bool hitsTriangleWith(const ObjectRay& ray, const Axes& axes, const TriangleVertices& tri) {
  TriangleHit th;
  return intersectWatertightWith(ray.wt, axes, tri.v0, tri.v1, tri.v2, ray.tfar, th);
}

/// Tests `tri` (mesh triangle `prim`) against `ray` for t in [tnear, ray.tfar]; when it is hit
/// and precedes `hit` (hitPrecedes), records it in `hit` and lowers ray.tfar to its t.
inline bool recordTriangleHit(ObjectRay& ray, const TriangleVertices& tri, std::uint32_t prim,
                              Hit& hit) {
  return recordTriangleHitWith(ray, RayAxes(ray.wt), tri, prim, hit);
}

/// Calls `f(axes)` with the ray's axis permutation as the FixedAxes equal to it, and returns
/// what f returns: a leaf's triangle loop is then compiled once per permutation (six, see
/// WatertightRay::shearAxes) and reads vertex components without run-time selection. A
/// permutation shearAxes cannot produce goes to f(RayAxes(ray)).
template <class F>
inline auto withFixedAxes(const WatertightRay& ray, const F& f) {
  switch (ray.kz * 3 + ray.kx) {
    case 0 * 3 + 1:
      return f(FixedAxes<1, 2, 0>{});
    case 0 * 3 + 2:
      return f(FixedAxes<2, 1, 0>{});
    case 1 * 3 + 2:
      return f(FixedAxes<2, 0, 1>{});
    case 1 * 3 + 0:
      return f(FixedAxes<0, 2, 1>{});
    case 2 * 3 + 0:
      return f(FixedAxes<0, 1, 2>{});
    case 2 * 3 + 1:
      return f(FixedAxes<1, 0, 2>{});
    default:
      return f(RayAxes(ray));
  }
}

}  // namespace tg::detail
