// Eight-wide twins of a BVH4's nodes, for single-ray walks that test eight boxes per 256-bit
// instruction (Bvh8Walk.h). Internal header: not installed.
#pragma once

#include <cstdint>
#include <vector>

#include "Bvh4.h"

namespace tg::detail {

/// A node of eight slots, with Bvh4Node's slot conventions (inner: count 0 and a node index;
/// leaf: count > 0 and the first primitive; unused: count 0, kInvalidId and an empty box). An
/// inner slot holds the index of a BVH4 node, whose twin has the same index.
struct alignas(64) Bvh8Node {
  /// bounds[2 * axis] lower, bounds[2 * axis + 1] upper coordinates of the eight slots.
  float bounds[6][8];
  /// Node index (inner) or first primitive (leaf) per slot.
  std::uint32_t child[8];
  /// Primitive count per slot; 0 for inner and unused slots.
  std::uint32_t count[8];
};

/// The twins of a BVH4's nodes, indexed as the nodes.
using Bvh8NodeArray = std::vector<Bvh8Node, DefaultInitAllocator<Bvh8Node>>;

/// Writes into `twins` one twin per node of `nodes`: the node's slots, with its inner slots
/// replaced by their own children, widest box first, while the eight slots hold them.
void buildBvh8Twins(const Bvh4NodeArray& nodes, Bvh8NodeArray& twins);

/// Writes into `wide` an eight-wide BVH collapsed from `nodes`, root first: the root's twin
/// and, depth first, the twins of the nodes its inner slots reach, whose inner slots then hold
/// indices into `wide` (a node a twin opens gets no twin of its own), so that each node is
/// followed by its first inner child.
void buildBvh8(const Bvh4NodeArray& nodes, Bvh8NodeArray& wide);

}  // namespace tg::detail
