// Front-to-back kd-tree traversal shared by the object kd-trees and the top-level kd-tree
// (Havran's recursive traversal in iterative form), robust to +-0 direction components and
// to rays lying in split planes. Internal header: not installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "tracegraph/backend/KdTree.h"

namespace tg::detail {

/// Relative slack on cell-interval ends: three float roundings of the slab computation.
inline constexpr float kIntervalSlack = 3.0f * 0x1p-24f;

/// Distance along the ray to the plane `pos`. A ray starting on the plane is at distance 0
/// even when 1/d overflowed to infinity (0 * inf would be NaN).
inline float planeDistance(float pos, float origin, float inverseDirection) {
  const float d = pos - origin;
  return d == 0.0f ? 0.0f : d * inverseDirection;
}

/// Clips [tmin, tmax] to the box. Zero direction components never reach a multiplication with
/// infinity: a ray parallel to a slab is inside it or misses the box.
inline bool clipToBox(const Box3f& box, const Vec3f& origin, const Vec3f& direction,
                      const Vec3f& inverseDirection, float& tmin, float& tmax) {
  if (box.empty()) return false;
  for (int a = 0; a < 3; ++a) {
    const float o = origin[a];
    if (direction[a] == 0.0f) {
      if (o < box.lower[a] || o > box.upper[a]) return false;
      continue;
    }
    float t0 = planeDistance(box.lower[a], o, inverseDirection[a]);
    float t1 = planeDistance(box.upper[a], o, inverseDirection[a]);
    if (t0 > t1) std::swap(t0, t1);
    // Widen by the rounding of the two operations above so that a grazing ray is kept.
    t0 -= std::abs(t0) * kIntervalSlack;
    t1 += std::abs(t1) * kIntervalSlack;
    tmin = std::max(tmin, t0);
    tmax = std::min(tmax, t1);
  }
  return tmin <= tmax;
}

/// Walks the leaves a ray segment [tnear, tfar] crosses, front to back. `leaf(first, count)`
/// tests the references primIndices[first, first+count) and returns true when it found a hit
/// (it lowers `tfar` itself for closest-hit queries). Any-hit queries stop at the first hit;
/// closest-hit queries stop once the closest hit lies strictly before the current cell's exit
/// (an exact tie at the border goes on, so the id tie-break sees every candidate).
template <bool AnyHit, class LeafFn>
bool traverseKdTree(const std::vector<KdNode>& nodes, const Box3f& bounds, const Vec3f& origin,
                    const Vec3f& direction, const Vec3f& inverseDirection, float tnear,
                    const float& tfar, std::uint64_t& nodeVisits, LeafFn&& leaf) {
  struct StackEntry {
    std::uint32_t node;
    float tmin, tmax;
  };
  float tmin = tnear, tmax = tfar;
  if (!clipToBox(bounds, origin, direction, inverseDirection, tmin, tmax)) return false;

  StackEntry stack[kKdMaxDepth + 2];
  int stackSize = 0;
  std::uint32_t nodeIndex = 0;
  bool found = false;
  for (;;) {
    const KdNode* node = &nodes[nodeIndex];
    while (!node->isLeaf()) {
      ++nodeVisits;
      const int axis = node->axis();
      const float split = node->split();
      const float o = origin[axis];
      const float d = direction[axis];
      const std::uint32_t below = nodeIndex + 1, above = node->aboveChild();
      // The near child holds the origin; on the plane itself the direction decides.
      const bool belowFirst = o < split || (o == split && d <= 0.0f);
      const std::uint32_t nearChild = belowFirst ? below : above;
      const std::uint32_t farChild = belowFirst ? above : below;
      if (d == 0.0f) {
        // Parallel to the plane: only a ray lying *in* the plane can touch both children.
        if (o == split) stack[stackSize++] = {farChild, tmin, tmax};
        nodeIndex = nearChild;
      } else {
        // tsplit <= 0: the plane is behind the origin, or the origin lies on it and the ray
        // moves into the near child (chosen by its direction above); either way it never
        // reaches the far child.
        const float tsplit = planeDistance(split, o, inverseDirection[axis]);
        if (tsplit <= 0.0f || tsplit > tmax) {
          nodeIndex = nearChild;
        } else if (tsplit < tmin) {
          nodeIndex = farChild;
        } else {
          stack[stackSize++] = {farChild, tsplit, tmax};
          nodeIndex = nearChild;
          tmax = tsplit;
        }
      }
      node = &nodes[nodeIndex];
    }

    if (leaf(node->firstPrim(), node->primCount())) {
      if constexpr (AnyHit) return true;
      found = true;
    }
    if constexpr (!AnyHit) {
      if (found && tfar < tmax) return true;
    }
    // Pop the next far cell whose interval still starts before the closest hit.
    for (;;) {
      if (stackSize == 0) return found;
      const StackEntry e = stack[--stackSize];
      if (e.tmin > tfar) continue;
      nodeIndex = e.node;
      tmin = e.tmin;
      tmax = e.tmax;
      break;
    }
  }
}

}  // namespace tg::detail
