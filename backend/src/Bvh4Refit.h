// Bottom-up box updates of a BVH4 whose topology stays (refit), and the SAH cost gathered on the
// same pass. SSE throughout, as the builders (BvhBinning.h). Internal header: not installed.
#pragma once

#include <tbb/parallel_for.h>

#include <cstdint>

#include "Bvh4.h"
#include "BvhBinning.h"

namespace tg::detail {

/// Partial sums of bvh4SahCost over a subtree, so that a pass that already visits every slot
/// bottom-up gets the cost without a second walk over the nodes.
struct Bvh4SahSum {
  /// Sum of cost times slot area.
  double weighted = 0.0;
  /// Sum of cost alone: the weights bvh4SahCost uses when the root has no area.
  double flat = 0.0;

  /// Adds a slot with box `box` whose visit costs `cost`.
  void addSlot(const Box3f& box, double cost) { addSlot(box.area(), cost); }
  /// Adds a slot whose box has surface area `area` (as Box3f::area gives it).
  void addSlot(float area, double cost) {
    weighted += cost * double(area);
    flat += cost;
  }
  /// Adds a subtree's sums.
  void add(const Bvh4SahSum& o) {
    weighted += o.weighted;
    flat += o.flat;
  }
  /// bvh4SahCost of a tree whose root node's slots sum to this and whose root box is `root`.
  double finish(const Box3f& root, double traversalCost) const {
    const double rootArea = root.area();
    if (!(rootArea > 0.0)) return traversalCost + flat;
    return (traversalCost * rootArea + weighted) / rootArea;
  }
};

/// Recomputes the slot boxes of node `index` and of its subtree, children before parents, and
/// returns the union of its slots; `sum` receives the subtree's SAH sums.
///
/// `leafBox(first, count, acc)` gives a leaf slot's box as an SseBox and may gather more per
/// leaf into `acc` (any type with merge(const Acc&), e.g. counts of what the leaves hold). When
/// `parallelLevels` > 0, that many top levels refit their children as parallel tasks, each
/// with its own default-constructed Acc merged in slot order afterwards; sums are combined in
/// slot order too, so nothing depends on the thread count.
///
/// Boxes stay in SSE registers from the leaves up: a node's four slots are written as its six
/// rows by two transposes, and their areas are taken as Box3f::area takes them (SseBox::area),
/// so the boxes and sums are those of a walk with Box3f. Callgrind, a refit of 65,536 triangles
/// (leaf boxes in SSE too, BvhAccel.cpp): 17.4M instructions with Box3f boxes, 12.2M now.
template <class Acc, class LeafBox>
SseBox refitBvh4(Bvh4NodeArray& nodes, std::uint32_t index, const LeafBox& leafBox,
                 double traversalCost, double intersectionCost, int parallelLevels, Bvh4SahSum& sum,
                 Acc& acc) {
  Bvh4Node& node = nodes[index];
#if defined(__GNUC__)
  // Children lie far apart in the array, so each would be a cache miss when its turn comes:
  // ask for both lines of every inner child now, while the first subtree is being refitted.
  for (int s = 0; s < 4; ++s) {
    if (node.count[s] != 0 || node.child[s] == kInvalidId) continue;
    const char* child = reinterpret_cast<const char*>(&nodes[node.child[s]]);
    __builtin_prefetch(child);
    __builtin_prefetch(child + 64);
  }
#endif
  SseBox boxes[4];  // unused slots keep the empty box (+inf, -inf), as Bvh4Node::makeEmpty
  Bvh4SahSum sums[4];
  if (parallelLevels > 0) {
    Acc accs[4];
    tbb::parallel_for(0, 4, [&](int s) {
      if (node.child[s] == kInvalidId) return;
      boxes[s] = node.count[s] != 0
                     ? leafBox(node.child[s], node.count[s], accs[s])
                     : refitBvh4(nodes, node.child[s], leafBox, traversalCost, intersectionCost,
                                 parallelLevels - 1, sums[s], accs[s]);
    });
    for (int s = 0; s < 4; ++s) acc.merge(accs[s]);
  } else {
    for (int s = 0; s < 4; ++s) {
      if (node.child[s] == kInvalidId) continue;
      boxes[s] = node.count[s] != 0 ? leafBox(node.child[s], node.count[s], acc)
                                    : refitBvh4(nodes, node.child[s], leafBox, traversalCost,
                                                intersectionCost, 0, sums[s], acc);
    }
  }
  __m128 lx = boxes[0].lower, ly = boxes[1].lower, lz = boxes[2].lower, l3 = boxes[3].lower;
  __m128 ux = boxes[0].upper, uy = boxes[1].upper, uz = boxes[2].upper, u3 = boxes[3].upper;
  _MM_TRANSPOSE4_PS(lx, ly, lz, l3);
  _MM_TRANSPOSE4_PS(ux, uy, uz, u3);
  _mm_store_ps(node.bounds[0], lx);
  _mm_store_ps(node.bounds[1], ux);
  _mm_store_ps(node.bounds[2], ly);
  _mm_store_ps(node.bounds[3], uy);
  _mm_store_ps(node.bounds[4], lz);
  _mm_store_ps(node.bounds[5], uz);
  SseBox all;
  for (int s = 0; s < 4; ++s) {
    if (node.child[s] == kInvalidId) continue;
    all.extend(boxes[s]);
    const bool leaf = node.count[s] != 0;
    sum.addSlot(boxes[s].area(), leaf ? intersectionCost * node.count[s] : traversalCost);
    if (!leaf) sum.add(sums[s]);
  }
  return all;
}

/// An Acc for refitBvh4 that gathers nothing.
struct NoLeafData {
  void merge(const NoLeafData&) {}
};

}  // namespace tg::detail
