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

/// The slots of node `i`'s twin: its own, with the widest inner slot whose children fit opened
/// into its children, until none does (a ray that enters a wide box is the likeliest to enter
/// its children too). Returns how many (at most eight).
int twinSlots(const Bvh4NodeArray& nodes, std::size_t i, Slot slots[8]) {
  int n = 0;
  for (int s = 0; s < 4; ++s)
    if (used(nodes[i], s))
      slots[n++] = Slot{nodes[i].slotBounds(s), nodes[i].child[s], nodes[i].count[s]};
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
    if (best < 0) return n;
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
}

/// Writes the `n` slots into `out`, the rest unused.
void writeSlots(const Slot slots[8], int n, Bvh8Node& out) {
  for (int s = 0; s < 8; ++s) {
    const bool live = s < n;
    for (int a = 0; a < 3; ++a) {
      out.bounds[2 * a][s] = live ? slots[s].box.lower[a] : std::numeric_limits<float>::infinity();
      out.bounds[2 * a + 1][s] =
          live ? slots[s].box.upper[a] : -std::numeric_limits<float>::infinity();
    }
    out.child[s] = live ? slots[s].child : kInvalidId;
    out.count[s] = live ? slots[s].count : 0;
  }
}

/// Appends the twin of BVH4 node `i` to `wide` and then, depth first, those of the nodes its
/// inner slots hold, whose indices in `wide` replace theirs; returns its index.
std::uint32_t appendWideNode(const Bvh4NodeArray& nodes, std::uint32_t i, Bvh8NodeArray& wide) {
  Slot slots[8];
  const int n = twinSlots(nodes, i, slots);
  const auto index = static_cast<std::uint32_t>(wide.size());
  wide.emplace_back();
  for (int k = 0; k < n; ++k)
    if (slots[k].count == 0) slots[k].child = appendWideNode(nodes, slots[k].child, wide);
  writeSlots(slots, n, wide[index]);
  return index;
}

}  // namespace

void buildBvh8(const Bvh4NodeArray& nodes, Bvh8NodeArray& wide) {
  wide.clear();
  if (nodes.empty()) return;
  wide.reserve(nodes.size());
  appendWideNode(nodes, 0, wide);
  // A static tree is kept for many frames: hold what it uses (about half the BVH4's count).
  wide.shrink_to_fit();
}

void buildBvh8BelowRoot(const Bvh4NodeArray& nodes, Bvh4Node& root, Bvh8NodeArray& wide) {
  wide.clear();
  if (nodes.empty()) return;
  root = nodes[0];
  wide.reserve(nodes.size());
  for (int s = 0; s < 4; ++s)
    if (root.isInner(s)) root.child[s] = appendWideNode(nodes, root.child[s], wide);
}

}  // namespace tg::detail
