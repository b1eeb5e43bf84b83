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

/// A BVH4 node that has a wide node of its own: where a walk entering the tree at that node
/// (a top level's subtree entry) enters the eight-wide tree.
struct Bvh8Entry {
  std::uint32_t bvh4Node;  ///< index in the BVH4
  std::uint32_t wideNode;  ///< index in the eight-wide tree
};

/// BVH4 levels below the root whose nodes buildBvh8 gives entries (the root is level 0).
inline constexpr int kBvh8EntryDepth = 3;

/// Writes into `wide` an eight-wide BVH collapsed from `nodes`, root first, nodes depth first,
/// each followed by its first inner child. The collapse sees each BVH4 node as
/// a binary tree (its slots paired as lowHalf in Bvh8Twin.cpp pairs them) and picks, by dynamic
/// programming, the eight-wide tree over the same leaves whose nodes have the smallest summed
/// surface area (Ylitie, Karras and Laine 2017): inner nodes mostly hold eight children, and
/// their boxes are unions of BVH4 slot boxes.
///
/// With `entries`, every inner BVH4 node of the first kBvh8EntryDepth levels below the root
/// (of two or more slots) also gets a wide node that stands for its subtree, listed in
/// `entries` sorted by BVH4 node: the tree's own when the collapse made one for the node's
/// slots, else one appended after the tree, whose descendants are the tree's wherever the
/// collapse of that subtree alone meets it (the dynamic programme's answer for a part does not
/// depend on where the part sits). Walks from the root thus keep the smallest-cost tree, and a
/// top level that enters a subtree walks it eight-wide as well, for a few extra nodes.
void buildBvh8(const Bvh4NodeArray& nodes, Bvh8NodeArray& wide,
               std::vector<Bvh8Entry>* entries = nullptr);

/// buildBvh8 below the root: writes into `wide` the eight-wide trees of the root's inner
/// children and into `root` a copy of the root node whose inner slots hold their indices in
/// `wide` (for walks that test the root four-wide, see traverseBvh8).
void buildBvh8BelowRoot(const Bvh4NodeArray& nodes, Bvh4Node& root, Bvh8NodeArray& wide);

}  // namespace tg::detail
