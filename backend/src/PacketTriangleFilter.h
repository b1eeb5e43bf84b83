// The watertight inside test over the lanes of a packet, written once for any SIMD width: each
// kernel translation unit instantiates it with its vector type. Internal linkage only (see
// PacketKernel.h). Internal header: not installed.
//
// V must provide: V::kWidth lanes; V::load(const float*), V::broadcast(float), +, -, * and
// V::candidates(U, V, W) returning, as a bit mask, the lanes where the scalar test could accept
// (see TriangleFilterFn). Plain +, -, * on the vector types keep the scalar order of
// operations; the kernels are compiled without floating-point contraction.
#pragma once

#include "PacketKernel.h"

namespace tg::detail {
namespace {

template <class V>
void filterTrianglesWith(const float* vertices, std::uint32_t count, const PacketTriangleRays& rays,
                         unsigned lanes, unsigned* candidates) {
  const int kx = rays.kx, ky = rays.ky, kz = rays.kz;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float* tri = vertices + 9 * i;
    unsigned mask = 0;
    for (unsigned h = 0; h < kPacketLanes; h += V::kWidth) {
      if (((lanes >> h) & ((1u << V::kWidth) - 1u)) == 0) continue;
      const V ox = V::load(rays.origin[kx] + h), oy = V::load(rays.origin[ky] + h),
              oz = V::load(rays.origin[kz] + h);
      const V sx = V::load(rays.sx + h), sy = V::load(rays.sy + h);
      // A = a - origin, then the shear: ax = A[kx] - sx * A[kz], as in intersectWatertight.
      const V az = V::broadcast(tri[kz]) - oz, bz = V::broadcast(tri[3 + kz]) - oz,
              cz = V::broadcast(tri[6 + kz]) - oz;
      const V ax = (V::broadcast(tri[kx]) - ox) - sx * az;
      const V ay = (V::broadcast(tri[ky]) - oy) - sy * az;
      const V bx = (V::broadcast(tri[3 + kx]) - ox) - sx * bz;
      const V by = (V::broadcast(tri[3 + ky]) - oy) - sy * bz;
      const V cx = (V::broadcast(tri[6 + kx]) - ox) - sx * cz;
      const V cy = (V::broadcast(tri[6 + ky]) - oy) - sy * cz;
      const V u = cx * by - cy * bx;
      const V v = ax * cy - ay * cx;
      const V w = bx * ay - by * ax;
      mask |= V::candidates(u, v, w) << h;
    }
    candidates[i] = mask & lanes;
  }
}

}  // namespace
}  // namespace tg::detail
