// The leaf step every object accelerator shares: one watertight triangle test and the tie rule.
// Internal header: not installed.
#pragma once

#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/ObjectAccel.h"

namespace tg::detail {

/// Tests `tri` (mesh triangle `prim`) against `ray` for t in [tnear, ray.tfar]; when it is hit
/// and precedes `hit` (hitPrecedes), records it in `hit` and lowers ray.tfar to its t.
inline bool recordTriangleHit(ObjectRay& ray, const TriangleVertices& tri, std::uint32_t prim,
                              Hit& hit) {
  TriangleHit th;
  if (!intersectWatertight(ray.wt, tri.v0, tri.v1, tri.v2, ray.tfar, th)) return false;
  if (!hitPrecedes(th.t, ray.instanceId, prim, hit)) return false;
  hit.t = th.t;
  hit.u = th.u;
  hit.v = th.v;
  hit.primId = prim;
  hit.instanceId = ray.instanceId;
  hit.objectId = ray.objectId;
  ray.tfar = th.t;
  return true;
}

}  // namespace tg::detail
