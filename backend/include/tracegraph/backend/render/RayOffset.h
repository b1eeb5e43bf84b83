/// @file RayOffset.h
/// Robust starting points for secondary rays (hard cases 13-15).
///
/// A hit point computed in floating point lies near, not on, the surface; a ray started there
/// can hit the very triangle it leaves ("acne") or, started from the wrong side, pass through a
/// thin object. Following pbrt-v4's offset-ray-origin idea, the origin is pushed off the
/// surface along the geometric normal by a bound on the error, never by a fixed epsilon:
///
/// 1. The hit point o + t d is evaluated in double and projected onto the plane of the hit
///    triangle (world-space vertices in double), which removes the error of t, however far the
///    ray travelled, and leaves only the float rounding of the result.
/// 2. The bound then covers what the *next* intersection test can get wrong about which side of
///    the plane the origin is on: float rounding of the vertices relative to the origin and of
///    the shear, i.e. a few ulps of the largest magnitude involved. We use
///    error = kOffsetUlps * 2^-24 * max(|p|_inf, |v0|_inf, |v1|_inf, |v2|_inf)
///    per component, and move the origin by error * |n|_1 along n, rounded away from the
///    surface, which is at least kOffsetUlps/2 ulps of max(|p.x|, |p.y|, |p.z|).
///
/// The offset thus scales with the scene's magnitude: at a translation of 10^6 it is about half
/// a unit, at the unit scale 5e-7 units, so a 1e-4-thick slab of unit size is not skipped and
/// contact shadows stay correct down to gaps of about 1e-6 of the scene's magnitude.
#pragma once

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Scene.h"

namespace tg {

/// Offset scale, in units of 2^-24 relative to the largest magnitude (see the file comment).
/// Measured: with the projection of step 1, a scale of 1 already gave no self-intersection in
/// 4 million grazing and non-grazing rays off tilted, rotated, scaled and instanced triangles up
/// to 3e6 units wide at translations up to 10^6 (0.25 gave a few); 8 leaves an 8x margin while
/// keeping offsets small enough for contact shadows and thin glass.
inline constexpr float kOffsetUlps = 8.0f;

/// A hit point prepared for spawning secondary rays.
struct SurfacePoint {
  Vec3f position;         ///< on the hit triangle's plane up to float rounding
  Vec3f geometricNormal;  ///< unit world geometric normal of the hit triangle (as in Hit)
  float error = 0.0f;     ///< per-component bound on the position's distance from the surface
};

/// Refines `hit` (found along `ray` in `scene`) into a SurfacePoint (see the file comment).
SurfacePoint refineHitPoint(const Scene& scene, const Ray& ray, const Hit& hit);

/// The origin for a ray leaving `sp` in direction `w`: offset to the side of the surface that
/// `w` points into, so reflection rays start above and refraction rays below the surface.
Vec3f offsetRayOrigin(const SurfacePoint& sp, const Vec3f& w);

/// A ray from `sp` in direction `w` (tnear 0, tfar infinity), origin offset to w's side.
Ray spawnRay(const SurfacePoint& sp, const Vec3f& w);
/// spawnRay written into `out` field by field, for rays stored in a table: a returned Ray is
/// copied in 16-byte moves from a slot written in narrower stores, which the processor cannot
/// forward (the copy waits for the stores to reach the cache).
void spawnRay(const SurfacePoint& sp, const Vec3f& w, Ray& out);

/// A shadow ray from `sp` towards the point `target`: direction target - origin, tnear 0, and
/// tfar just short of 1 by the same kind of relative bound, so that geometry *at* the target
/// (a light placed on a surface) does not occlude it. tfar is 0 when the target is within the
/// error bound of the origin; treat such a target as visible.
Ray spawnRayTo(const SurfacePoint& sp, const Vec3f& target);
/// spawnRayTo written into `out` field by field (see spawnRay).
void spawnRayTo(const SurfacePoint& sp, const Vec3f& target, Ray& out);
/// True when offsetRayOrigin(sp, w) offsets to the side the geometric normal points away from
/// (dot(w, n) < 0): the origin depends on `w` only through this side, so rays from one point
/// can share the two origins.
inline bool leavesBelow(const SurfacePoint& sp, const Vec3f& w) {
  return dot(w, sp.geometricNormal) < 0.0f;
}
/// spawnRayTo(sp, target, out) given its origin, offsetRayOrigin(sp, target - sp.position)
/// (computed once per side of the surface for the shadow rays of several lights).
void spawnRayFrom(const Vec3f& origin, const Vec3f& target, Ray& out);

}  // namespace tg
