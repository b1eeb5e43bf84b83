/// @file KdTree.h
/// The kd-tree shared by the SAH builder and the paper's fast builder, and its traversal.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "tracegraph/backend/ObjectAccel.h"

namespace tg {

/// A triangle's three vertices, copied out of the mesh for cache-friendly leaf tests.
struct TriangleVertices {
  ///@{
  /// The vertices, in the mesh's winding order.
  Vec3f v0, v1, v2;
  ///@}
};

/// An 8-byte kd-tree node (pbrt/Havran layout).
///
/// Inner node: `bits` holds the split position (a float), `flags & 3` the axis, and
/// `flags >> 2` the index of the child *above* the plane; the child below the plane is
/// the next node in the array. Leaf: `flags & 3 == 3`, `flags >> 2` the number of triangle
/// references and `bits` the first of them in KdTree::primIndices.
struct KdNode {
  /// Split position (inner) or first reference (leaf).
  std::uint32_t bits = 0;
  /// Low 2 bits: axis, or 3 for a leaf; higher bits: above child (inner) or count (leaf).
  std::uint32_t flags = 3;

  /// A leaf of `count` references starting at `firstRef`.
  static KdNode makeLeaf(std::uint32_t firstRef, std::uint32_t count) {
    return KdNode{firstRef, (count << 2) | 3u};
  }
  /// An inner node splitting `axis` at `split`.
  static KdNode makeInner(int axis, float split, std::uint32_t aboveChild) {
    return KdNode{std::bit_cast<std::uint32_t>(split),
                  (aboveChild << 2) | static_cast<std::uint32_t>(axis)};
  }
  /// True for leaves.
  bool isLeaf() const { return (flags & 3u) == 3u; }
  /// Split axis of an inner node (0: x, 1: y, 2: z).
  int axis() const { return static_cast<int>(flags & 3u); }
  /// Split position of an inner node.
  float split() const { return std::bit_cast<float>(bits); }
  /// Index of the child above the split plane (inner node).
  std::uint32_t aboveChild() const { return flags >> 2; }
  /// Number of triangle references (leaf).
  std::uint32_t primCount() const { return flags >> 2; }
  /// Index of the first reference in KdTree::primIndices (leaf).
  std::uint32_t firstPrim() const { return bits; }
};

/// Largest tree depth any builder produces (bounds the traversal stack).
inline constexpr int kKdMaxDepth = 64;
/// Largest number of references a leaf may hold (30 bits in KdNode::flags).
inline constexpr std::uint32_t kKdMaxLeafCount = (1u << 30) - 1;

/// A built kd-tree: nodes (root at index 0), leaf reference lists and the bounds it covers.
struct KdTree {
  /// The nodes, root first.
  std::vector<KdNode> nodes;
  std::vector<std::uint32_t> primIndices;  ///< triangle ids, grouped by leaf
  Box3f bounds;                            ///< root cell (bounds of non-degenerate triangles)
  /// What the build produced.
  BuildStats stats;
};

/// Options of the SAH builder (Wald & Havran 2006, "On building fast kd-trees for ray tracing,
/// and on doing that in O(N log N)").
struct SahKdTreeOptions {
  float traversalCost = 1.0f;     ///< K_T
  float intersectionCost = 1.5f;  ///< K_I
  float emptyBonus = 0.8f;        ///< lambda: SAH cost factor when one side is empty
  int maxDepth = 0;               ///< 0: 8 + 1.3 log2(n), capped at kKdMaxDepth
};

/// Options of the paper's fast builder for deforming objects: spatial-median splits in the
/// dimension of largest extent, and a leaf tolerance that grows with depth, so that deep
/// subtrees stop early instead of splitting tiny clusters the next frame discards anyway.
struct FastKdTreeOptions {
  std::uint32_t leafSize = 2;      ///< leaf when at most this many triangles at depth 0
  float leafSizeGrowth = 0.25f;    ///< extra triangles tolerated per level of depth
  int maxDepth = 0;                ///< 0: 2 log2(n) + 4, capped at kKdMaxDepth
};

/// Builds a SAH kd-tree over `triangles`. Triangles for which `isDegenerateTriangle` holds are
/// left out and counted in stats.degenerate. Empty input gives a single empty leaf.
KdTree buildSahKdTree(const std::vector<TriangleVertices>& triangles,
                      const SahKdTreeOptions& options = {});

/// Builds the paper's fast kd-tree over `triangles` (same conventions as buildSahKdTree).
KdTree buildFastKdTree(const std::vector<TriangleVertices>& triangles,
                       const FastKdTreeOptions& options = {});

/// Closest-hit traversal of a built kd-tree (front to back, stack of far children, mailboxed).
bool intersectKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles,
                     ObjectRay& ray, Hit& hit, TraversalContext& ctx);
/// Any-hit traversal of a built kd-tree.
bool occludedKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles,
                    const ObjectRay& ray, TraversalContext& ctx);

/// Checks the structural invariants of a tree: child indices in range, splits inside their
/// cells, every non-degenerate triangle referenced by every leaf whose cell it overlaps.
/// Returns an empty string or the first violation. Used by tests.
std::string validateKdTree(const KdTree& tree, const std::vector<TriangleVertices>& triangles);

}  // namespace tg
