// The object rays of a packet entering one instance, with their divisions done several lanes at
// a time. Internal header: not installed.
#pragma once

#include <algorithm>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "PacketKernel.h"
#include "PacketRays.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg::detail {

/// The watertight test's per-lane constants of eight directions, given as rows of lanes: the
/// axis permutation (kz, the first largest |direction| component as maxDimension picks it, as
/// the bits of zIsX and zIsY, neither meaning z; the swap of kx and ky when dir[kz] < 0), the
/// shear constants and the reciprocal direction. Quotients are correctly rounded whether
/// computed alone or four to a vector, so every value equals WatertightRay's.
struct PacketShear {
  unsigned zIsX = 0;                             ///< lanes whose kz is x
  unsigned zIsY = 0;                             ///< lanes whose kz is y
  unsigned swapped = 0;                          ///< lanes whose dir[kz] < 0
  alignas(16) float sx[kRayPacketSize];          ///< WatertightRay::sx per lane
  alignas(16) float sy[kRayPacketSize];          ///< WatertightRay::sy per lane
  alignas(16) float inverse[3][kRayPacketSize];  ///< 1 / direction per axis and lane

  /// kz of lane `l` (0, 1 or 2).
  int kz(unsigned l) const { return (zIsX >> l) & 1u ? 0 : ((zIsY >> l) & 1u ? 1 : 2); }
  /// The lanes of `lanes` whose axis permutation is lane `lead`'s.
  unsigned samePermutation(unsigned lanes, unsigned lead) const {
    const auto same = [&](unsigned bits) { return (bits >> lead) & 1u ? bits : ~bits; };
    return lanes & same(zIsX) & same(zIsY) & same(swapped);
  }
};

/// Fills `out` from the direction rows xRow, yRow and zRow (16-byte aligned, kRayPacketSize
/// lanes each), four lanes per instruction where SSE is available. Every lane is computed:
/// lanes nobody uses give numbers nobody reads.
inline void shearPacket(const float* xRow, const float* yRow, const float* zRow, PacketShear& out) {
  unsigned zIsX = 0, zIsY = 0, swapped = 0;
  float* sx = out.sx;
  float* sy = out.sy;
  float(&inverse)[3][kRayPacketSize] = out.inverse;
#if defined(__SSE2__)
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  const auto select = [](__m128 mask, __m128 a, __m128 b) {
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
  };
  for (unsigned h = 0; h < kRayPacketSize; h += 4) {
    const __m128 dx = _mm_load_ps(xRow + h), dy = _mm_load_ps(yRow + h), dz = _mm_load_ps(zRow + h);
    const __m128 ax = _mm_and_ps(dx, absMask), ay = _mm_and_ps(dy, absMask),
                 az = _mm_and_ps(dz, absMask);
    const __m128 xGeY = _mm_cmpge_ps(ax, ay);
    const __m128 x = _mm_and_ps(xGeY, _mm_cmpge_ps(ax, az));
    const __m128 y = _mm_andnot_ps(xGeY, _mm_cmpge_ps(ay, az));
    // kz = x: (kx, ky) = (y, z); kz = y: (z, x); kz = z: (x, y); swapped when dir[kz] < 0.
    const __m128 dkz = select(x, dx, select(y, dy, dz));
    const __m128 dkx = select(x, dy, select(y, dz, dx));
    const __m128 dky = select(x, dz, select(y, dx, dy));
    const __m128 swap = _mm_cmplt_ps(dkz, zero);
    _mm_store_ps(sx + h, _mm_div_ps(select(swap, dky, dkx), dkz));
    _mm_store_ps(sy + h, _mm_div_ps(select(swap, dkx, dky), dkz));
    _mm_store_ps(inverse[0] + h, _mm_div_ps(one, dx));
    _mm_store_ps(inverse[1] + h, _mm_div_ps(one, dy));
    _mm_store_ps(inverse[2] + h, _mm_div_ps(one, dz));
    zIsX |= static_cast<unsigned>(_mm_movemask_ps(x)) << h;
    zIsY |= static_cast<unsigned>(_mm_movemask_ps(y)) << h;
    swapped |= static_cast<unsigned>(_mm_movemask_ps(swap)) << h;
  }
#else
  for (unsigned l = 0; l < kRayPacketSize; ++l) {
    const Vec3f dir{xRow[l], yRow[l], zRow[l]};
    const int kz = maxDimension(abs(dir));
    zIsX |= (kz == 0 ? 1u : 0u) << l;
    zIsY |= (kz == 1 ? 1u : 0u) << l;
    int kx = 0, ky = 0;
    WatertightRay::shearAxes(dir, kz, kx, ky);
    swapped |= (dir[kz] < 0.0f ? 1u : 0u) << l;
    sx[l] = dir[kx] / dir[kz];
    sy[l] = dir[ky] / dir[kz];
    for (int a = 0; a < 3; ++a) inverse[a][l] = 1.0f / dir[a];
  }
#endif
  out.zIsX = zIsX;
  out.zIsY = zIsY;
  out.swapped = swapped;
}

/// The IdentityRowsFn of the portable kernels: the rays' rows and their shear, four lanes at a
/// time (shearPacket), then the triangle rows of `lanes` (not empty) straight from them: what
/// BvhAccel::loadPacket gathers from the object rays of an identity instance, which are the
/// world rays (kx, ky and kz left to the caller). Lanes without the first lane's axis
/// permutation hold its values.
inline LoadedLanes loadIdentityRows(const Ray* rays, unsigned lanes, PacketTriangleRays& tri) {
  PacketRayRows rows;
  loadRayRows(rays, rows);
  PacketShear shear;
  shearPacket(rows.row[4], rows.row[5], rows.row[6], shear);
  // The permutation is fixed by kz and the swap: lanes whose three bits equal the first lane's.
  const unsigned lead = static_cast<unsigned>(__builtin_ctz(lanes));
  const unsigned filtered = shear.samePermutation(lanes, lead);
  const LoadedLanes found{lanes, filtered, shear.kz(lead), ((shear.swapped >> lead) & 1u) != 0};
#if defined(__SSE2__)
  if (filtered == (1u << kRayPacketSize) - 1u) {
    // Every lane takes the test (the common case): whole rows, doubles two lanes at a time.
    for (unsigned h = 0; h < kRayPacketSize; h += 4) {
      for (int a = 0; a < 3; ++a) {
        const __m128 o = _mm_load_ps(rows.row[a] + h), d = _mm_load_ps(rows.row[4 + a] + h);
        _mm_store_ps(tri.origin[a] + h, o);
        _mm_storeu_pd(tri.originD[a] + h, _mm_cvtps_pd(o));
        _mm_storeu_pd(tri.originD[a] + h + 2, _mm_cvtps_pd(_mm_movehl_ps(o, o)));
        _mm_storeu_pd(tri.directionD[a] + h, _mm_cvtps_pd(d));
        _mm_storeu_pd(tri.directionD[a] + h + 2, _mm_cvtps_pd(_mm_movehl_ps(d, d)));
      }
      _mm_store_ps(tri.sx + h, _mm_load_ps(shear.sx + h));
      _mm_store_ps(tri.sy + h, _mm_load_ps(shear.sy + h));
      _mm_store_ps(tri.tnear + h, _mm_load_ps(rows.row[3] + h));
    }
    return found;
  }
#endif
  for (unsigned l = 0; l < kRayPacketSize; ++l) {
    const unsigned from = (filtered >> l) & 1u ? l : lead;
    for (int a = 0; a < 3; ++a) {
      tri.origin[a][l] = rows.row[a][from];
      tri.originD[a][l] = rows.row[a][from];
      tri.directionD[a][l] = rows.row[4 + a][from];
    }
    tri.sx[l] = shear.sx[from];
    tri.sy[l] = shear.sy[from];
    tri.tnear[l] = rows.row[3][from];
  }
  return found;
}

/// Sets the axis permutation of `tri` from what a row load found of its first lane.
inline void setTrianglePermutation(const LoadedLanes& found, PacketTriangleRays& tri) {
  tri.kz = found.kz;
  WatertightRay::shearAxes(found.kz, found.kzNegative, tri.kx, tri.ky);
}

/// mapPacketToObject for an identity instance, whose object rays are the world rays: the axis
/// permutation, shear constants and reciprocals of all eight lanes from the rays' rows, four
/// lanes per instruction where SSE is available, then one pass of stores per lane. Choosing the
/// permutation per lane and scattering the divisions' operands were most of the scalar
/// mapping's work.
///
/// (A packet walk whose lanes all take the SIMD tests needs only their triangle rows: it loads
/// them with its kernels' loadIdentityRows and makes a lane's ray when a test needs it,
/// BvhAccel::packetLane. Writing every ray of the packet was a tenth of a museum packet's time
/// from outside.)
inline void mapIdentityPacket(const InstanceRecord& inst, const Ray* rays, unsigned lanes,
                              const float* tfar, ObjectRayPacket& out) {
  PacketRayRows rows;
  loadRayRows(rays, rows);
  PacketShear shear;
  shearPacket(rows.row[4], rows.row[5], rows.row[6], shear);
  const float* sx = shear.sx;
  const float* sy = shear.sy;
  const auto& inverse = shear.inverse;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    ObjectRay& r = out.rays[l];
    WatertightRay& wt = r.wt;
    wt.origin = {rows.row[0][l], rows.row[1][l], rows.row[2][l]};
    wt.direction = {rows.row[4][l], rows.row[5][l], rows.row[6][l]};
    wt.originD = Vec3d(wt.origin);
    wt.directionD = Vec3d(wt.direction);
    wt.tnear = rows.row[3][l];
    wt.kz = shear.kz(l);
    WatertightRay::shearAxes(wt.direction, wt.kz, wt.kx, wt.ky);
    wt.sx = sx[l];
    wt.sy = sy[l];
    r.inverseDirection = Vec3f(inverse[0][l], inverse[1][l], inverse[2][l]);
    wt.sz = inverse[wt.kz][l];
    r.tfar = tfar[l];
    r.instanceId = inst.instanceId;
    r.objectId = inst.objectId;
  }
}

/// Writes out.rays[l] = objectRayFor(inst, rays[l], tfar[l]) for every lane l of `lanes`, bit for
/// bit. Each object ray needs five divisions (the shear constants sx and sy, and the reciprocal
/// direction, whose kz component is sz): a packet entering an instance would pay forty scalar
/// divisions. Here they are vector divisions, four lanes at a time on x86-64, and a quotient is
/// correctly rounded whether computed alone or in a vector, so every field equals the scalar
/// constructor's. Every field of the lanes is written: `out` may be uninitialised storage.
inline void mapPacketToObject(const InstanceRecord& inst, const Ray* rays, unsigned lanes,
                              const float* tfar, ObjectRayPacket& out) {
  if (inst.identity) {
    mapIdentityPacket(inst, rays, lanes, tfar, out);
    return;
  }
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
    // As objectRayFor for a transformed instance: the ray is mapped in double, and the float
    // ray is the rounding of the double one.
    wt.originD = inst.worldToObjectD.transformPoint(Vec3d(ray.origin));
    wt.directionD = inst.worldToObjectD.transformVector(Vec3d(ray.direction));
    wt.origin = Vec3f(wt.originD);
    wt.direction = Vec3f(wt.directionD);
    wt.tnear = ray.tnear;
    // The axis permutation of WatertightRay's constructor.
    const Vec3f& dir = wt.direction;
    wt.kz = maxDimension(abs(dir));
    WatertightRay::shearAxes(dir, wt.kz, wt.kx, wt.ky);
    numerator[0][l] = dir[wt.kx];
    numerator[1][l] = dir[wt.ky];
    denominator[0][l] = dir[wt.kz];
    denominator[1][l] = dir[wt.kz];
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
