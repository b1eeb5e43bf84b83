// Binned-SAH construction of 4-wide BVHs over primitive boxes, shared by the object BVHs
// (triangles) and the top-level BVH (instances), and the SAH cost that guides refit-or-rebuild.
// Internal header: not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "Bvh4.h"

namespace tg::detail {

/// A primitive as the builder moves it between node ranges: its box and the caller's id
/// (32 bytes, so that partitioning moves two 16-byte halves).
struct alignas(16) BvhPrim {
  /// Box minimum.
  float lower[3];
  /// Caller's id (triangle or instance index).
  std::uint32_t id;
  /// Box maximum.
  float upper[3];
  /// Unused.
  std::uint32_t padding;

  /// From a box and an id.
  static BvhPrim make(const Box3f& b, std::uint32_t id) {
    return {{b.lower.x, b.lower.y, b.lower.z}, id, {b.upper.x, b.upper.y, b.upper.z}, 0};
  }
  /// The box.
  Box3f box() const { return {{lower[0], lower[1], lower[2]}, {upper[0], upper[1], upper[2]}}; }
};

/// Primitives as the builders take them. Default-initialising: a build writes every primitive
/// right after sizing the array, so a zero fill first would be a pass over memory for nothing
/// (on one thread, before the parallel fill).
using BvhPrimArray = std::vector<BvhPrim, DefaultInitAllocator<BvhPrim>>;

/// Builder settings; the defaults suit high-quality object BVHs.
struct BvhBuildOptions {
  /// Bins per axis of the SAH sweep (at most kMaxBins).
  int bins = 32;
  /// Bin along all three axes (true) or only along the widest centroid extent (false: about
  /// three times cheaper, for trees that are rebuilt every frame).
  bool allAxes = true;
  /// Largest leaf; bigger ranges are always split.
  std::uint32_t maxLeafSize = 4;
  /// SAH cost of visiting a node, relative to intersectionCost.
  float traversalCost = 1.0f;
  /// SAH cost of testing one primitive.
  float intersectionCost = 1.0f;
  /// Ranges with more primitives bin in parallel and build their subtrees as parallel tasks.
  std::size_t parallelThreshold = 4096;
  /// Ranges with more primitives are partitioned in chunks of this many, in parallel. The
  /// chunks depend on this alone, never on the thread count, so neither does the tree.
  std::size_t partitionChunk = std::size_t(1) << 14;

  /// Largest supported bin count.
  static constexpr int kMaxBins = 32;
};

/// What a build produced.
struct BvhBuildResult {
  /// BVH4 nodes, root first; empty when there were no primitives.
  Bvh4NodeArray nodes;
  /// Leaf slots.
  std::size_t leaves = 0;
  /// Deepest node level (root: 0).
  std::size_t maxDepth = 0;
  /// Bounds of all primitives.
  Box3f bounds;
  /// bvh4SahCost of the nodes with the builder's SAH weights, when the builder gathers it on
  /// the way (buildBvh4 and the Morton builder; summed in another order, so it may differ from
  /// bvh4SahCost in the last bits); negative otherwise.
  double sahCost = -1.0;
};

/// Bounds of a build's primitive boxes and of their centroids (each as lower + upper, twice
/// the centre), when the caller gathered them while making the primitives: the builder then
/// skips its own pass over them. They must be exactly those of `prims` (min and max are exact,
/// and lower + upper rounds as the builder's own sum).
struct BvhPrimBounds {
  Box3f bounds;     ///< union of the primitive boxes
  Box3f centroids;  ///< box of lower + upper of every primitive
};

/// Told of each node of a BVH4 under construction once its whole subtree is final, children
/// before their parents, on the thread that finished it (several threads call at once, for
/// disjoint subtrees). Work that runs bottom-up over the tree (the eight-wide collapse's
/// programme, Bvh8Twin.h) thus meets each node while the builder's thread still holds it in
/// its cache, instead of in a pass of its own afterwards.
class Bvh4BuildListener {
 public:
  virtual ~Bvh4BuildListener() = default;
  /// Node `index` of `nodes` and every node below it are written and will not change (other
  /// nodes of `nodes` may still be under construction).
  virtual void nodeBuilt(const Bvh4NodeArray& nodes, std::uint32_t index) = 0;
};

/// Builds a BVH4 over `prims` and reorders them so that every leaf's primitives are contiguous:
/// a leaf slot (child, count) refers to prims[child, child + count). `out.nodes` keeps its
/// capacity between builds, so per-frame rebuilds do not reallocate. Deterministic: the same
/// input gives the same tree whatever the number of threads (only node numbering may differ).
/// `known`, when given, holds the bounds of `prims` (see BvhPrimBounds). `listener`, when
/// given, is told of every node (see Bvh4BuildListener); the tree has at most prims.size()
/// nodes.
void buildBvh4(BvhPrimArray& prims, const BvhBuildOptions& options, BvhBuildResult& out,
               const BvhPrimBounds* known = nullptr, Bvh4BuildListener* listener = nullptr);

/// SAH cost of a BVH4: the expected cost of a ray that hits the root box, counting
/// `traversalCost` per node visited and `intersectionCost` per primitive tested, with the
/// probability of visiting a child taken as its area over the root's. A root of zero area (all
/// primitives in one point or line) counts every box as visited.
double bvh4SahCost(const Bvh4NodeArray& nodes, double traversalCost, double intersectionCost);

}  // namespace tg::detail
