#include "tracegraph/backend/render/RayOffset.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace tg {
namespace {

constexpr float kUnitRoundoff = 0x1p-24f;  // half an ulp of 1

float maxAbs(const Vec3f& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}
double maxAbs(const Vec3d& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

/// std::nextafter(x, up ? +inf : -inf) on the bits, as glibc computes it, without the library
/// call (three per secondary ray): the neighbouring float is the bit pattern one step away.
float nextFloat(float x, bool up) {
  auto bits = std::bit_cast<std::uint32_t>(x);
  const std::uint32_t magnitude = bits & 0x7FFFFFFFu;
  if (magnitude > 0x7F800000u) return x + (up ? kInfinity : -kInfinity);   // NaN
  if (magnitude == 0) return std::bit_cast<float>(up ? 1u : 0x80000001u);  // either zero
  if (x == (up ? kInfinity : -kInfinity)) return x;
  // Away from zero adds one to the magnitude, towards zero takes one off; an overflow of the
  // exponent gives the infinity, as nextafter does.
  const bool negative = (bits >> 31) != 0;
  bits = negative == up ? bits - 1 : bits + 1;
  return std::bit_cast<float>(bits);
}

}  // namespace

SurfacePoint refineHitPoint(const Scene& scene, const Ray& ray, const Hit& hit) {
  SurfacePoint sp;
  sp.geometricNormal = hit.geometricNormal;
  const TriangleMesh& mesh = scene.objectMesh(hit.objectId);
  const Affine3d& toWorld = scene.instanceTransform(hit.instanceId);
  Vec3d v[3];
  double magnitude = 0.0;
  for (int k = 0; k < 3; ++k) {
    v[k] = toWorld.transformPoint(Vec3d(mesh.positions[mesh.indices[3 * hit.primId + k]]));
    magnitude = std::max(magnitude, maxAbs(v[k]));
  }
  // o + t d in double, then projected onto the triangle's plane: the error of t (which grows
  // with the distance travelled and the size of the triangle) only slides the point within the
  // plane, where it does no harm.
  Vec3d p = Vec3d(ray.origin) + Vec3d(ray.direction) * static_cast<double>(hit.t);
  const Vec3d n = cross(v[1] - v[0], v[2] - v[0]);
  const double nn = dot(n, n);
  if (nn > 0.0 && std::isfinite(nn)) p = p - n * (dot(p - v[0], n) / nn);
  sp.position = Vec3f(p);
  magnitude = std::max(magnitude, static_cast<double>(maxAbs(sp.position)));
  sp.error = kOffsetUlps * kUnitRoundoff * static_cast<float>(magnitude);
  return sp;
}

Vec3f offsetRayOrigin(const SurfacePoint& sp, const Vec3f& w) {
  const Vec3f& n = sp.geometricNormal;
  const float distance = sp.error * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  Vec3f offset = n * distance;
  if (leavesBelow(sp, w)) offset = -offset;
  const Vec3f o = sp.position + offset;
  // The addition itself rounds; step one more ulp outwards so it can only round away. Written
  // per component (not through o[i]) so that the result stays in registers.
  auto outwards = [](float value, float by) {
    return by > 0.0f ? nextFloat(value, true) : by < 0.0f ? nextFloat(value, false) : value;
  };
  return {outwards(o.x, offset.x), outwards(o.y, offset.y), outwards(o.z, offset.z)};
}

void spawnRay(const SurfacePoint& sp, const Vec3f& w, Ray& out) {
  // Computed before `out` is written: w may be one of its fields.
  const Vec3f origin = offsetRayOrigin(sp, w);
  out.direction = w;  // before the origin: w may be out.origin
  out.origin = origin;
  out.tnear = 0.0f;
  out.tfar = kInfinity;
}

Ray spawnRay(const SurfacePoint& sp, const Vec3f& w) {
  Ray r;
  spawnRay(sp, w, r);
  return r;
}

void spawnRayTo(const SurfacePoint& sp, const Vec3f& target, Ray& out) {
  // Computed before `out` is written: target may be one of its fields.
  spawnRayFrom(offsetRayOrigin(sp, target - sp.position), target, out);
}

void spawnRayFrom(const Vec3f& origin, const Vec3f& target, Ray& out) {
  // Both read before `out` is written: either may be one of its fields.
  const Vec3f direction = target - origin;
  // Stop short of the target by a bound of the same kind as the origin offset, relative to the
  // larger of the two magnitudes, plus a few ulps for the rounding of t itself.
  const float magnitude = std::max(maxAbs(target), maxAbs(origin));
  const float len = length(direction);
  const float shortfall =
      len > 0.0f ? kOffsetUlps * kUnitRoundoff * magnitude / len + 4.0f * kUnitRoundoff : 1.0f;
  out.origin = origin;
  out.tnear = 0.0f;
  out.direction = direction;
  out.tfar = std::max(0.0f, 1.0f - shortfall);
}

Ray spawnRayTo(const SurfacePoint& sp, const Vec3f& target) {
  Ray r;
  spawnRayTo(sp, target, r);
  return r;
}

}  // namespace tg
