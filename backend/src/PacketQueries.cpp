// Lane-by-lane packet queries: the defaults of ObjectAccel and TopLevelAccel, used by the
// accelerators without a packet walk (the kd-trees) and as the fallback of those with one.
#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg {

unsigned ObjectAccel::intersectPacket(ObjectRayPacket& packet, unsigned lanes, Hit* hits,
                                      TraversalContext& ctx) const {
  unsigned changed = 0;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    if (intersect(packet.rays[l], hits[l], ctx)) changed |= 1u << l;
  }
  return changed;
}

unsigned ObjectAccel::occludedPacket(const ObjectRayPacket& packet, unsigned lanes,
                                     TraversalContext& ctx) const {
  unsigned blocked = 0;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    if (occluded(packet.rays[l], ctx)) blocked |= 1u << l;
  }
  return blocked;
}

void TopLevelAccel::intersectPacket(const Ray* rays, unsigned lanes, Hit* hits,
                                    TraversalContext& ctx) const {
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    if (isTraceable(rays[l])) intersect(rays[l], hits[l], ctx);
  }
}

void TopLevelAccel::intersectPacketPair(const Ray* rays, unsigned lanes, Hit* hits,
                                        TraversalContext& ctx) const {
  constexpr unsigned kPacketMask = (1u << kRayPacketSize) - 1u;
  for (unsigned h = 0; h < 2; ++h) {
    const unsigned half = (lanes >> (kRayPacketSize * h)) & kPacketMask;
    if (half != 0) intersectPacket(rays + kRayPacketSize * h, half, hits + kRayPacketSize * h, ctx);
  }
}

unsigned TopLevelAccel::occludedPacketPair(const Ray* rays, unsigned lanes,
                                           TraversalContext& ctx) const {
  constexpr unsigned kPacketMask = (1u << kRayPacketSize) - 1u;
  unsigned blocked = 0;
  for (unsigned h = 0; h < 2; ++h) {
    const unsigned half = (lanes >> (kRayPacketSize * h)) & kPacketMask;
    if (half != 0)
      blocked |= occludedPacket(rays + kRayPacketSize * h, half, ctx) << (kRayPacketSize * h);
  }
  return blocked;
}

unsigned TopLevelAccel::occludedPacket(const Ray* rays, unsigned lanes,
                                       TraversalContext& ctx) const {
  unsigned blocked = 0;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    if (isTraceable(rays[l]) && occluded(rays[l], ctx)) blocked |= 1u << l;
  }
  return blocked;
}

}  // namespace tg
