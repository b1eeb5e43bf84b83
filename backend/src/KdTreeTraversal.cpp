// Object-level kd-tree queries: the shared traversal with mailboxed watertight leaf tests.
#include "KdTraversal.h"
#include "LeafTest.h"

namespace tg {

bool intersectKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles,
                     ObjectRay& ray, Hit& hit, TraversalContext& ctx) {
  ctx.mailbox.clear();
  return detail::traverseKdTree<false>(
      tree.nodes, tree.bounds, ray.wt.origin, ray.wt.direction, ray.inverseDirection, ray.wt.tnear,
      ray.tfar, ctx.nodeVisits, [&](std::uint32_t first, std::uint32_t count) {
        bool found = false;
        for (std::uint32_t i = 0; i < count; ++i) {
          const std::uint32_t prim = tree.primIndices[first + i];
          if (ctx.mailbox.testAndSet(prim)) continue;
          ++ctx.triangleTests;
          found |= detail::recordTriangleHit(ray, triangles[prim], prim, hit);
        }
        return found;
      });
}

bool occludedKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles,
                    const ObjectRay& ray, TraversalContext& ctx) {
  ctx.mailbox.clear();
  return detail::traverseKdTree<true>(
      tree.nodes, tree.bounds, ray.wt.origin, ray.wt.direction, ray.inverseDirection, ray.wt.tnear,
      ray.tfar, ctx.nodeVisits, [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t i = 0; i < count; ++i) {
          const std::uint32_t prim = tree.primIndices[first + i];
          if (ctx.mailbox.testAndSet(prim)) continue;
          ++ctx.triangleTests;
          const TriangleVertices& tri = triangles[prim];
          TriangleHit th;
          if (intersectWatertight(ray.wt, tri.v0, tri.v1, tri.v2, ray.tfar, th)) return true;
        }
        return false;
      });
}

}  // namespace tg
