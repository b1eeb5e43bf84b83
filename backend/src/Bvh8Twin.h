// Eight-wide BVHs collapsed from a BVH4, for single-ray walks that test eight boxes per 256-bit
// instruction (Bvh8Walk.h). Internal header: not installed.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "Bvh4.h"
#include "BvhBuilder.h"

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

/// How the collapse's programme stands for one part of a BVH4 node (its used slots, or a pair
/// of them): three per node, the node's slots first, then its pairs. Sixteen bytes, kept apart
/// from the part's costs (Bvh8PartCosts), which only the programme reads: the appending of the
/// wide nodes reads these long after the build wrote them, and waits on every cache line it
/// loads. With the two in one 48-byte record the BART kitchen's nodes took 2.9-3.2 ms to append
/// on one thread (medians of 39 builds in each of three processes), apart 1.7-1.8 ms; on two
/// threads 2.6 -> 1.6 ms.
struct Bvh8PartChoice {
  /// Three bits per budget i of 2 to 8 (bits 3(i - 2) up): the roots given to the first half
  /// when spread over i roots, 0 when one wide node of its own is cheaper; bits 21 to 23: the
  /// roots of its first half when it is a wide node of its own (eight in all).
  std::uint32_t choices;
  /// Its halves, normalised to a node's used slots or a leaf slot: their nodes, then their
  /// masks with bit 4 set for a leaf.
  std::uint32_t halfNode[2];
  std::uint8_t halfMask[2];
  /// The part's slots; 0 for a pair slot that the node does not have.
  std::uint8_t mask;

  /// Roots of the first half when the part is spread over `i` roots (0: a node of its own).
  int firstRoots(int i) const { return i < 2 ? 0 : (choices >> (3 * (i - 2))) & 7u; }
  /// Roots of the first half when the part is a wide node of its own.
  int ownFirst() const { return (choices >> 21) & 7u; }
};

/// The costs of one part (as Bvh8PartChoice): cost[i - 1] is the cheapest node cost of the
/// part's subtree with at most i roots.
struct Bvh8PartCosts {
  float cost[8];
};

/// The collapse's dynamic programme, solved node by node while the BVH4 is built (as its
/// Bvh4BuildListener) or over a finished tree (solveTree), children before parents. Solved in
/// the builder's tasks, each node is read while its thread still holds it in cache: as a pass
/// of its own after the build, the flattened BART kitchen's programme took 2.7-3.1 ms of a
/// two-thread build (see BvhAccel::buildSah).
///
/// The parts are kept in blocks of kNodesPerBlock nodes, allocated as the first node of each
/// is solved: a build does not know its node count until it ends, and one array for the worst
/// case (as many nodes as primitives, five times what SAH trees use) came from fresh pages on
/// every build of the BART kitchen, about 600 page faults each; blocks of this size are reused
/// by the allocator.
class Bvh8CollapsePlan final : public Bvh4BuildListener {
 public:
  Bvh8CollapsePlan();
  ~Bvh8CollapsePlan() override;
  Bvh8CollapsePlan(const Bvh8CollapsePlan&) = delete;
  Bvh8CollapsePlan& operator=(const Bvh8CollapsePlan&) = delete;

  /// Forgets every solved node and makes room for trees of up to `maxNodes` nodes.
  void reset(std::size_t maxNodes);
  /// Solves the parts of node `index` (below the `maxNodes` of reset), whose children are
  /// solved. Safe to call from several threads at once for different nodes.
  void nodeBuilt(const Bvh4NodeArray& nodes, std::uint32_t index) override;
  /// Solves every node of the finished tree `nodes` (its first levels' subtrees in parallel).
  void solveTree(const Bvh4NodeArray& nodes);
  /// Solve the programme's budgets eight at a time with AVX2 (`on`, the default where the CPU
  /// runs AVX2) or one at a time; both give the same bits. For tests that compare the two.
  void setVectorSolve(bool on);
  /// Whether the budgets are solved eight at a time.
  bool vectorSolve() const { return vectorSolve_; }
  /// How the three parts of a solved node are stood for: its used slots, then its pairs.
  Bvh8PartChoice* choicesOf(std::uint32_t node) const {
    return blockOf(node).choice + 3 * (node % kNodesPerBlock);
  }
  /// The costs of the three parts of a solved node, in the order of choicesOf.
  Bvh8PartCosts* costsOf(std::uint32_t node) const {
    return blockOf(node).costs + 3 * (node % kNodesPerBlock);
  }

 private:
  /// Nodes per block: 72 KiB, below the size from which glibc maps fresh pages for every
  /// allocation (128 KiB by default).
  static constexpr std::uint32_t kNodesPerBlock = 512;
  /// The parts of kNodesPerBlock consecutive nodes.
  struct Block {
    Bvh8PartChoice choice[3 * kNodesPerBlock];
    Bvh8PartCosts costs[3 * kNodesPerBlock];
  };
  Block& blockOf(std::uint32_t node) const {
    return *blocks_[node / kNodesPerBlock].load(std::memory_order_acquire);
  }
  void solveSubtree(const Bvh4NodeArray& nodes, std::uint32_t index, int depth);
  void release();
  std::unique_ptr<std::atomic<Block*>[]> blocks_;
  std::size_t blockCount_ = 0;
  bool vectorSolve_;
};

/// buildBvh8 from a plan already solved over every node of `nodes`.
void buildBvh8(const Bvh4NodeArray& nodes, const Bvh8CollapsePlan& plan, Bvh8NodeArray& wide,
               std::vector<Bvh8Entry>* entries = nullptr);

/// buildBvh8 below the root: writes into `wide` the eight-wide trees of the root's inner
/// children and into `root` a copy of the root node whose inner slots hold their indices in
/// `wide` (for walks that test the root four-wide, see traverseBvh8).
void buildBvh8BelowRoot(const Bvh4NodeArray& nodes, Bvh4Node& root, Bvh8NodeArray& wide);

}  // namespace tg::detail
