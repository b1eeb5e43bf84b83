// The object rays of a packet entering one instance, with their divisions done several lanes at
// a time. Internal header: not installed.
#pragma once

#include <algorithm>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "tracegraph/backend/TopLevelAccel.h"

namespace tg::detail {

/// Writes out.rays[l] = objectRayFor(inst, rays[l], tfar[l]) for every lane l of `lanes`, bit for
/// bit. Each object ray needs five divisions (the shear constants sx and sy, and the reciprocal
/// direction, whose kz component is sz): a packet entering an instance would pay forty scalar
/// divisions. Here they are vector divisions, four lanes at a time on x86-64, and a quotient is
/// correctly rounded whether computed alone or in a vector, so every field equals the scalar
/// constructor's. Every field of the lanes is written: `out` may be uninitialised storage.
inline void mapPacketToObject(const InstanceRecord& inst, const Ray* rays, unsigned lanes,
                              const float* tfar, ObjectRayPacket& out) {
  constexpr unsigned kLanes = kRayPacketSize;
  // Rows: sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], then 1 / dir.x, 1 / dir.y, 1 / dir.z.
  // Lanes outside `lanes` divide 1 by 1.
  alignas(16) float numerator[5][kLanes];
  alignas(16) float denominator[5][kLanes];
  alignas(16) float quotient[5][kLanes];
  for (int q = 0; q < 5; ++q) {
    std::fill(numerator[q], numerator[q] + kLanes, 1.0f);
    std::fill(denominator[q], denominator[q] + kLanes, 1.0f);
  }
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    ObjectRay& r = out.rays[l];
    WatertightRay& wt = r.wt;
    const Ray& ray = rays[l];
    // As objectRayFor: an identity instance takes the float ray as it is; any other maps it in
    // double, and the float ray is the rounding of the double one.
    if (inst.identity) {
      wt.origin = ray.origin;
      wt.direction = ray.direction;
      wt.originD = Vec3d(ray.origin);
      wt.directionD = Vec3d(ray.direction);
    } else {
      wt.originD = inst.worldToObjectD.transformPoint(Vec3d(ray.origin));
      wt.directionD = inst.worldToObjectD.transformVector(Vec3d(ray.direction));
      wt.origin = Vec3f(wt.originD);
      wt.direction = Vec3f(wt.directionD);
    }
    wt.tnear = ray.tnear;
    // The axis permutation of WatertightRay's constructor.
    const Vec3f& dir = wt.direction;
    const int kz = maxDimension(abs(dir));
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < 0.0f) std::swap(kx, ky);
    wt.kx = kx;
    wt.ky = ky;
    wt.kz = kz;
    numerator[0][l] = dir[kx];
    numerator[1][l] = dir[ky];
    denominator[0][l] = dir[kz];
    denominator[1][l] = dir[kz];
    denominator[2][l] = dir.x;
    denominator[3][l] = dir.y;
    denominator[4][l] = dir.z;
    r.tfar = tfar[l];
    r.instanceId = inst.instanceId;
    r.objectId = inst.objectId;
  }
  for (int q = 0; q < 5; ++q) {
#if defined(__SSE2__)
    for (unsigned h = 0; h < kLanes; h += 4)
      _mm_store_ps(quotient[q] + h,
                   _mm_div_ps(_mm_load_ps(numerator[q] + h), _mm_load_ps(denominator[q] + h)));
#else
    for (unsigned l = 0; l < kLanes; ++l) quotient[q][l] = numerator[q][l] / denominator[q][l];
#endif
  }
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    ObjectRay& r = out.rays[l];
    r.wt.sx = quotient[0][l];
    r.wt.sy = quotient[1][l];
    r.inverseDirection = Vec3f(quotient[2][l], quotient[3][l], quotient[4][l]);
    r.wt.sz = r.inverseDirection[static_cast<std::size_t>(r.wt.kz)];
  }
}

}  // namespace tg::detail
