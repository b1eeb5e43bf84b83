// A packet entering a transformed instance's BVH, loaded straight from the world rays. Internal
// header: not installed.
#pragma once

#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "BvhAccel.h"
#include "PacketObjectRays.h"

namespace tg::detail {

/// The object rays of a packet in a transformed instance as rows of lanes: the rounded float
/// ray the inside test and the box test read, and the double ray t is refined on.
struct TransformedPacketRows {
  alignas(16) float origin[3][kRayPacketSize];       ///< WatertightRay::origin per axis and lane
  alignas(16) float direction[3][kRayPacketSize];    ///< WatertightRay::direction
  alignas(16) double originD[3][kRayPacketSize];     ///< WatertightRay::originD
  alignas(16) double directionD[3][kRayPacketSize];  ///< WatertightRay::directionD
};

/// Maps the eight rays of `world` (all are read) through `m` as objectRayFor does, lane by lane:
/// the double mapping's products and sums in the order of Affine3::transformPoint and
/// transformVector, then one rounding to float. SSE2 takes two lanes per instruction; with
/// neither fused multiply-adds nor reassociation, each lane's numbers are the scalar ones.
inline void mapPacketRows(const Affine3d& m, const PacketRayRows& world,
                          TransformedPacketRows& out) {
#if defined(__SSE2__)
  for (unsigned h = 0; h < kRayPacketSize; h += 2) {
    const auto load2 = [&](int row) {
      return _mm_cvtps_pd(
          _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(world.row[row] + h))));
    };
    const __m128d ox = load2(0), oy = load2(1), oz = load2(2);
    const __m128d dx = load2(4), dy = load2(5), dz = load2(6);
    for (int r = 0; r < 3; ++r) {
      const __m128d m0 = _mm_set1_pd(m.m[r][0]), m1 = _mm_set1_pd(m.m[r][1]),
                    m2 = _mm_set1_pd(m.m[r][2]);
      const __m128d o = _mm_add_pd(
          _mm_add_pd(_mm_add_pd(_mm_mul_pd(m0, ox), _mm_mul_pd(m1, oy)), _mm_mul_pd(m2, oz)),
          _mm_set1_pd(m.m[r][3]));
      const __m128d d =
          _mm_add_pd(_mm_add_pd(_mm_mul_pd(m0, dx), _mm_mul_pd(m1, dy)), _mm_mul_pd(m2, dz));
      _mm_store_pd(out.originD[r] + h, o);
      _mm_store_pd(out.directionD[r] + h, d);
      _mm_storel_pi(reinterpret_cast<__m64*>(out.origin[r] + h), _mm_cvtpd_ps(o));
      _mm_storel_pi(reinterpret_cast<__m64*>(out.direction[r] + h), _mm_cvtpd_ps(d));
    }
  }
#else
  for (unsigned l = 0; l < kRayPacketSize; ++l) {
    const Vec3d o = m.transformPoint(Vec3d(world.row[0][l], world.row[1][l], world.row[2][l]));
    const Vec3d d = m.transformVector(Vec3d(world.row[4][l], world.row[5][l], world.row[6][l]));
    for (int a = 0; a < 3; ++a) {
      out.originD[a][l] = o[a];
      out.directionD[a][l] = d[a];
      out.origin[a][l] = static_cast<float>(o[a]);
      out.direction[a][l] = static_cast<float>(d[a]);
    }
  }
#endif
}

/// The TransformedRowsFn of the portable kernels: the lanes mapped as rows (mapPacketRows), their
/// shear and reciprocals four lanes at a time (shearPacket), then the rows BvhAccel::loadPacket
/// would write.
inline LoadedLanes loadTransformedRows(const Ray* rays, const Affine3d& worldToObject,
                                       unsigned lanes, const float* tfar, PacketBoxRays& box,
                                       PacketTriangleRays& tri) {
  PacketRayRows world;
  loadRayRows(rays, world);
  TransformedPacketRows object;
  mapPacketRows(worldToObject, world, object);
  PacketShear shear;
  shearPacket(object.direction[0], object.direction[1], object.direction[2], shear);

  // Box rows (BvhAccel::loadPacket): the lanes whose direction signs match the first lane's.
  const unsigned first = static_cast<unsigned>(__builtin_ctz(lanes));
  unsigned negative[3] = {0, 0, 0};
  for (unsigned l = 0; l < kRayPacketSize; ++l)
    for (int a = 0; a < 3; ++a) negative[a] |= (object.direction[a][l] < 0.0f ? 1u : 0u) << l;
  unsigned coherent = lanes;
  unsigned signs = 0;
  for (int a = 0; a < 3; ++a) {
    const bool lead = (negative[a] >> first) & 1u;
    coherent &= lead ? negative[a] : ~negative[a];
    signs |= (lead ? 1u : 0u) << a;
  }
  for (int a = 0; a < 3; ++a)
    for (unsigned l = 0; l < kRayPacketSize; ++l) {
      box.origin[a][l] = object.origin[a][l];
      // Bvh4Ray's reciprocal: +inf for a zero component whatever its sign.
      box.reciprocal[a][l] = object.direction[a][l] == 0.0f ? std::numeric_limits<float>::infinity()
                                                            : shear.inverse[a][l];
    }
  for (unsigned l = 0; l < kRayPacketSize; ++l) box.tnear[l] = world.row[3][l];
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    box.tfar[l] = tfar[l];
  }
  box.signs = signs;
  fillUnusedLanes(box, coherent, first);

  // Triangle rows: the coherent lanes with the first lane's axis permutation; the others hold
  // the first lane's numbers.
  const unsigned filtered = shear.samePermutation(coherent, first);
  for (unsigned l = 0; l < kRayPacketSize; ++l) {
    const unsigned from = (filtered >> l) & 1u ? l : first;
    for (int a = 0; a < 3; ++a) {
      tri.origin[a][l] = object.origin[a][from];
      tri.originD[a][l] = object.originD[a][from];
      tri.directionD[a][l] = object.directionD[a][from];
    }
    tri.sx[l] = shear.sx[from];
    tri.sy[l] = shear.sy[from];
    tri.tnear[l] = world.row[3][from];
  }
  return {coherent, filtered, shear.kz(first), ((shear.swapped >> first) & 1u) != 0};
}

/// What mapPacketToObject and BvhAccel::loadPacket together make of the lanes `lanes` (not
/// empty) of `rays` (eight rays, all read) entering transformed instance `inst`, lane l limited to
/// tfar[l], computed as rows of lanes by the kernels' loadTransformedRows without writing the
/// object rays: `loaded` gets the box and triangle rows (coherent: the lanes with the first
/// lane's object-space direction signs; filtered: those of them with its axis permutation), and
/// `packet` only the tfar and ids of `lanes`, which are left in loaded.unmappedLanes for
/// BvhAccel::packetLane to complete when a test reads a whole ray. Gathering every field of eight
/// object rays back into rows was an eighth of a packet's time in the robots' rigid parts.
inline void loadTransformedPacket(const InstanceRecord& inst, const Ray* rays, unsigned lanes,
                                  const float* tfar, const PacketKernels& kernels,
                                  ObjectRayPacket& packet, BvhPacketRays& loaded) {
  const LoadedLanes found = kernels.loadTransformedRows(rays, inst.worldToObjectD, lanes, tfar,
                                                        loaded.box, loaded.triangles);
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    ObjectRay& r = packet.rays[l];
    r.tfar = tfar[l];
    r.instanceId = inst.instanceId;
    r.objectId = inst.objectId;
  }
  setTrianglePermutation(found, loaded.triangles);
  loaded.coherent = found.coherent;
  loaded.filtered = found.filtered;
  loaded.unmappedLanes = lanes;
  loaded.worldRays = rays;
  loaded.instance = &inst;
  loaded.kernels = &kernels;
}

}  // namespace tg::detail
