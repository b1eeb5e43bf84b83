// Eight-wide BVHs collapsed from a BVH4, for single-ray walks that test eight boxes per 256-bit
// instruction (Bvh8Walk.h). Internal header: not installed.
#pragma once

#include <cstdint>
#include <vector>

#include "Bvh4.h"

namespace tg::detail {

/// A node of eight slots, with Bvh4Node's slot conventions (inner: count 0 and a node index;
/// leaf: count > 0 and the first primitive; unused: count 0, kInvalidId and an empty box). An
/// inner slot holds the index of another Bvh8Node of the same array.
struct alignas(64) Bvh8Node {
  /// bounds[2 * axis] lower, bounds[2 * axis + 1] upper coordinates of the eight slots.
  float bounds[6][8];
  /// Node index (inner) or first primitive (leaf) per slot.
  std::uint32_t child[8];
  /// Primitive count per slot; 0 for inner and unused slots.
  std::uint32_t count[8];
};

/// The nodes of an eight-wide BVH.
using Bvh8NodeArray = std::vector<Bvh8Node, DefaultInitAllocator<Bvh8Node>>;

/// Writes into `wide` an eight-wide BVH collapsed from `nodes`, root first. Each BVH4 node the
/// collapse reaches gets a twin: its own slots, with the widest inner slot whose children fit
/// opened into them, until none does (a ray that enters a wide box is the likeliest to enter
/// its children too); a node opened into its parent's twin gets none. Twins follow each other
/// depth first, each followed by its first inner child, and hold the indices of their inner
/// children's twins in `wide`: about half the BVH4's count of nodes.
void buildBvh8(const Bvh4NodeArray& nodes, Bvh8NodeArray& wide);

/// buildBvh8 below the root: writes into `wide` the eight-wide trees of the root's inner
/// children and into `root` a copy of the root node whose inner slots hold their indices in
/// `wide` (for walks that test the root four-wide, see traverseBvh8).
void buildBvh8BelowRoot(const Bvh4NodeArray& nodes, Bvh4Node& root, Bvh8NodeArray& wide);

}  // namespace tg::detail
