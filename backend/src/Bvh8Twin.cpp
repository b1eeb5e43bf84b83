// Eight-wide twins of BVH4 nodes (see Bvh8Twin.h).
#include "Bvh8Twin.h"

#include <limits>

namespace tg::detail {
namespace {

/// True when slot `s` of `node` holds a child (inner or leaf).
bool used(const Bvh4Node& node, int s) {
  return node.child[s] != kInvalidId || node.count[s] != 0;
}

/// One slot of a twin under construction.
struct Slot {
  Box3f box;
  std::uint32_t child, count;
};

}  // namespace

void buildBvh8Twins(const Bvh4NodeArray& nodes, Bvh8NodeArray& twins) {
  twins.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    Slot slots[8];
    int n = 0;
    for (int s = 0; s < 4; ++s)
      if (used(nodes[i], s))
        slots[n++] = Slot{nodes[i].slotBounds(s), nodes[i].child[s], nodes[i].count[s]};
    // Open the widest inner slot whose children fit, until none does: a ray that enters a
    // wide box is the likeliest to enter its children too.
    for (;;) {
      int best = -1;
      float bestArea = -1.0f;
      for (int k = 0; k < n; ++k) {
        if (slots[k].count != 0) continue;
        const Bvh4Node& c = nodes[slots[k].child];
        int children = 0;
        for (int s = 0; s < 4; ++s) children += used(c, s) ? 1 : 0;
        if (children == 0 || n - 1 + children > 8) continue;
        const float area = slots[k].box.area();
        if (area > bestArea) {
          best = k;
          bestArea = area;
        }
      }
      if (best < 0) break;
      const Bvh4Node& c = nodes[slots[best].child];
      bool first = true;
      for (int s = 0; s < 4; ++s) {
        if (!used(c, s)) continue;
        const Slot slot{c.slotBounds(s), c.child[s], c.count[s]};
        if (first) {
          slots[best] = slot;
          first = false;
        } else {
          slots[n++] = slot;
        }
      }
    }
    Bvh8Node& out = twins[i];
    for (int s = 0; s < 8; ++s) {
      const bool live = s < n;
      for (int a = 0; a < 3; ++a) {
        out.bounds[2 * a][s] =
            live ? slots[s].box.lower[a] : std::numeric_limits<float>::infinity();
        out.bounds[2 * a + 1][s] =
            live ? slots[s].box.upper[a] : -std::numeric_limits<float>::infinity();
      }
      out.child[s] = live ? slots[s].child : kInvalidId;
      out.count[s] = live ? slots[s].count : 0;
    }
  }
}

}  // namespace tg::detail
