// The structural check of a BVH4 shared by the builder tests: every node reachable and numbered
// after its parent, unused slots empty, leaf sizes within the limit, every primitive position
// counted per leaf that holds it, and slot boxes that hold what lies below them (exactly, for
// builders that promise tight boxes). Needs backend/src on the include path.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "Bvh4.h"

namespace tg::test {

/// What a walk from the root found.
struct Bvh4TreeCheck {
  std::size_t nodesVisited = 0;
  std::size_t leaves = 0;
  std::size_t maxDepth = 0;
  std::size_t errors = 0;
  std::string firstError;
  /// Depth-first description of the tree (slot kinds, counts, first primitives, boxes): equal
  /// for equal trees whatever numbering their nodes got.
  std::vector<float> shape;

  /// Records a finding; the first one is kept for the message.
  void fail(const std::string& what) {
    if (errors++ == 0) firstError = what;
  }
};

/// How a slot's box must relate to the boxes below it.
enum class SlotBoxRule {
  Exact,      ///< the union of what lies below, bit for bit (binned SAH)
  Enclosing,  ///< contains what lies below (Morton build and refit)
};

/// What the walk requires.
struct Bvh4WalkRules {
  /// Largest leaf.
  std::uint32_t maxLeaf = 4;
  /// Leaves above maxLeaf allowed (primitives no plane separates).
  bool allowBigLeaves = false;
  /// Slot boxes against their contents.
  SlotBoxRule boxes = SlotBoxRule::Enclosing;
};

/// Bit-for-bit equality of two boxes.
inline bool sameBox(const Box3f& a, const Box3f& b) {
  for (int k = 0; k < 3; ++k)
    if (a.lower[k] != b.lower[k] || a.upper[k] != b.upper[k]) return false;
  return true;
}

/// True when `outer` contains `inner` (always for an empty inner box).
inline bool encloses(const Box3f& outer, const Box3f& inner) {
  return inner.empty() || outer.contains(inner);
}

/// Checks node `index` (at `depth`) and below against the primitive boxes in leaf order and
/// returns the union of its slots. `seen[k]` counts the leaves that reference position k.
inline Box3f walkBvh4(const detail::Bvh4NodeArray& nodes, std::uint32_t index, std::size_t depth,
                      const std::vector<Box3f>& prims, const Bvh4WalkRules& rules,
                      std::vector<int>& seen, Bvh4TreeCheck& c) {
  ++c.nodesVisited;
  c.maxDepth = std::max(c.maxDepth, depth);
  const detail::Bvh4Node& node = nodes[index];
  Box3f all;
  int used = 0;
  for (int s = 0; s < 4; ++s) {
    const Box3f slot = node.slotBounds(s);
    if (node.child[s] == kInvalidId) {
      c.shape.push_back(-1.0f);
      if (node.count[s] != 0 || !slot.empty()) c.fail("unused slot with a box or count");
      continue;
    }
    ++used;
    Box3f inside;
    if (node.count[s] != 0) {
      ++c.leaves;
      c.shape.push_back(static_cast<float>(node.count[s]));
      c.shape.push_back(static_cast<float>(node.child[s]));
      if (node.count[s] > rules.maxLeaf && !rules.allowBigLeaves)
        c.fail("leaf above the size limit");
      if (std::size_t{node.child[s]} + node.count[s] > prims.size()) {
        c.fail("leaf past the primitives");
        continue;
      }
      for (std::uint32_t k = node.child[s]; k < node.child[s] + node.count[s]; ++k) {
        ++seen[k];
        inside.extend(prims[k]);
      }
    } else {
      c.shape.push_back(0.0f);
      if (node.child[s] <= index || node.child[s] >= nodes.size()) {
        c.fail("child not numbered after its parent");
        continue;
      }
      inside = walkBvh4(nodes, node.child[s], depth + 1, prims, rules, seen, c);
    }
    if (rules.boxes == SlotBoxRule::Exact ? !sameBox(slot, inside) : !encloses(slot, inside))
      c.fail(rules.boxes == SlotBoxRule::Exact ? "slot box is not the union of its contents"
                                               : "slot box misses what lies below it");
    for (int k = 0; k < 3; ++k) {
      c.shape.push_back(slot.lower[k]);
      c.shape.push_back(slot.upper[k]);
    }
    all.extend(slot);
  }
  if (used == 0) c.fail("node without children");
  if (used == 1 && index != 0) c.fail("inner node with a single child");
  return all;
}

}  // namespace tg::test
