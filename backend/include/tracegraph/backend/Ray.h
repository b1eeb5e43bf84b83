/// @file Ray.h
/// Rays and hit records shared by every accelerator and the renderer.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Marks "no id" in hit records and id tables.
inline constexpr std::uint32_t kInvalidId = 0xFFFFFFFFu;
/// Float infinity: tfar of unbounded rays, t of no hit.
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// A ray origin + t * direction for t in the closed interval [tnear, tfar].
///
/// Interval rule (hard case 11): a hit exactly at tnear or exactly at tfar counts. The direction
/// need not be unit length; hit distances are in units of the direction's length, and the
/// two-level traversal keeps them comparable across instances by never renormalising it.
struct Ray {
  /// Start point.
  Vec3f origin;
  /// Smallest t that counts.
  float tnear = 0.0f;
  /// Direction; t is measured in units of its length.
  Vec3f direction{0.0f, 0.0f, 1.0f};
  /// Largest t that counts.
  float tfar = kInfinity;
};

/// True for the rays a scene traces: finite origin and direction, a direction that is not
/// zero, and tnear <= tfar (neither NaN). Other rays never hit and are never occluded.
inline bool isTraceable(const Ray& ray) {
#if defined(__SSE2__)
  // The ray as its two 16-byte halves, (origin, tnear) and (direction, tfar): every test in a
  // few vector operations and one branch. The scalar form's dozen branches were a tenth of a
  // single ray's time for rays that miss a scene after a node or two.
  static_assert(sizeof(Ray) == 32 && offsetof(Ray, tnear) == 12 && offsetof(Ray, direction) == 16 &&
                offsetof(Ray, tfar) == 28);
  const __m128 a = _mm_loadu_ps(&ray.origin.x), b = _mm_loadu_ps(&ray.direction.x);
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 largest = _mm_set1_ps(std::numeric_limits<float>::max());
  // |x| <= max is false for infinities and NaN.
  const int finite = _mm_movemask_ps(_mm_cmple_ps(_mm_and_ps(a, magnitude), largest)) &
                     _mm_movemask_ps(_mm_cmple_ps(_mm_and_ps(b, magnitude), largest));
  const int zero = _mm_movemask_ps(_mm_cmpeq_ps(b, _mm_setzero_ps()));
  // tnear <= tfar is false when either is NaN.
  const int ordered = _mm_movemask_ps(_mm_cmple_ps(a, b)) >> 3;
  return (finite & 7) == 7 && (zero & 7) != 7 && ordered != 0;
#else
  return isFinite(ray.origin) && isFinite(ray.direction) &&
         !(ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) &&
         !std::isnan(ray.tnear) && !std::isnan(ray.tfar) && ray.tnear <= ray.tfar;
#endif
}

/// 1/d per component (+-inf for +-0 components): the reciprocal direction of ray set-ups. One
/// vector division where SSE is there, the same bits as three scalar divisions (each lane is
/// correctly rounded) for a third of the divider's time.
inline Vec3f reciprocals(const Vec3f& d) {
#if defined(__SSE2__)
  alignas(16) float r[4];
  _mm_store_ps(r, _mm_div_ps(_mm_set1_ps(1.0f), _mm_set_ps(1.0f, d.z, d.y, d.x)));
  return {r[0], r[1], r[2]};
#else
  return {1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
#endif
}

/// The closest hit along a ray.
///
/// Ties: when two triangles are hit at exactly the same float t, the one with the smaller
/// (instanceId, primId) wins, so the answer never depends on traversal order, accelerator or
/// thread count (hard case 2).
struct Hit {
  /// Distance along the ray in units of its direction; kInfinity: no hit.
  float t = kInfinity;
  ///@{
  /// Barycentrics: the hit point is (1-u-v)*v0 + u*v1 + v*v2 of the object-space triangle.
  float u = 0.0f, v = 0.0f;
  ///@}
  /// Instance hit (Scene::createInstance id).
  std::uint32_t instanceId = kInvalidId;
  /// Object of that instance.
  std::uint32_t objectId = kInvalidId;
  /// Triangle index within the object; kInvalidId: no hit.
  std::uint32_t primId = kInvalidId;
  /// World-space geometric normal, unit length, cross(v1-v0, v2-v0) mapped by the inverse
  /// transpose of the instance matrix.
  Vec3f geometricNormal;

  /// True when something was hit.
  bool valid() const { return primId != kInvalidId; }
};

/// Total order used to break exact ties in t (see Hit).
inline bool hitPrecedes(float t, std::uint32_t instanceId, std::uint32_t primId, const Hit& best) {
  if (t != best.t) return t < best.t;
  if (instanceId != best.instanceId) return instanceId < best.instanceId;
  return primId < best.primId;
}

}  // namespace tg
