// The paper's fast kd-tree builder for deforming objects: spatial-median splits in the dimension
// of largest cell extent, triangles classified by their bounding boxes, and a leaf tolerance that
// grows with depth. A tree is rebuilt every frame, so build speed matters more than the last few
// percent of traversal speed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/KdTree.h"

namespace tg {
namespace {

// Guard against runaway duplication. Large overlapping triangles straddle every median plane, and
// each level would nearly double the references down to the depth limit (hundreds of millions for
// a few thousand large triangles). A split whose SAH cost (with the SAH builder's default
// constants) exceeds the leaf's by more than kMaxCostRatio ends the subtree. The tolerance is
// generous because median planes are not chosen by cost: a split that looks poor on its own often
// pays off once its children are split again, so only clearly hopeless splits stop.
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectionCost = 1.5f;
constexpr float kMaxCostRatio = 1.25f;

template <int A>
inline float coord(const Vec3f& v) {
  if constexpr (A == 0) return v.x;
  if constexpr (A == 1) return v.y;
  return v.z;
}

class FastBuilder {
 public:
  FastBuilder(const std::vector<TriangleVertices>& triangles, const FastKdTreeOptions& options,
              KdTree& tree)
      : triangles_(triangles), options_(options), tree_(tree) {}

  void run() {
    const std::size_t n = triangles_.size();
    if (n > kKdMaxLeafCount) throw Error("buildFastKdTree: more than 2^30 - 1 triangles");
    // Room for the root list and a few levels below it; grows when a deep path needs more.
    reserveRefs(4 * n + 64);
    std::size_t count = 0;
    Box3f bounds;
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleVertices& t = triangles_[i];
      if (isDegenerateTriangle(t.v0, t.v1, t.v2)) {
        ++tree_.stats.degenerate;
        continue;
      }
      bounds.extend(t.v0);
      bounds.extend(t.v1);
      bounds.extend(t.v2);
      refs_[count++] = static_cast<std::uint32_t>(i);
    }
    tree_.bounds = bounds;
    const double log2n = std::log2(std::max(1.0, static_cast<double>(count)));
    maxDepth_ = std::min(kKdMaxDepth, options_.maxDepth > 0 ? options_.maxDepth
                                                            : static_cast<int>(2.0 * log2n + 4.0));
    tree_.nodes.reserve(count + 1);
    tree_.primIndices.reserve(2 * count);
    build(0, count, bounds, 0);
  }

 private:
  /// Builds the subtree over refs_[begin, end). The children's lists are written behind `end`
  /// (above first, below from the far end backwards), so the buffer works as a stack: the below
  /// child's subtree grows past both lists, the above child's subtree then reuses the dead below
  /// list. No per-node allocations; the buffer grows to a small multiple of the reference count.
  void build(std::size_t begin, std::size_t end, const Box3f& cell, int depth) {
    const auto nodeIndex = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    ++tree_.stats.nodes;
    const std::size_t count = end - begin;
    const float tolerance =
        static_cast<float>(options_.leafSize) + options_.leafSizeGrowth * static_cast<float>(depth);
    const float area = cell.area();
    if (static_cast<float>(count) <= tolerance || depth >= maxDepth_ || !(area > 0.0f)) {
      makeLeaf(nodeIndex, begin, end, depth);
      return;
    }
    const int a = maxDimension(cell.extent());
    const float lo = cell.lower[a], hi = cell.upper[a];
    // Halving each end first cannot overflow; the clamp guards the closed cell against rounding.
    const float split = std::clamp(0.5f * lo + 0.5f * hi, lo, hi);

    const std::size_t need = end + 2 * count;
    reserveRefs(need);
    std::size_t above = end, below = need;
    switch (a) {
      case 0:
        partition<0>(begin, end, split, above, below);
        break;
      case 1:
        partition<1>(begin, end, split, above, below);
        break;
      default:
        partition<2>(begin, end, split, above, below);
        break;
    }
    const std::size_t aboveCount = above - end, belowCount = need - below;

    Box3f belowCell = cell, aboveCell = cell;
    belowCell.upper[a] = split;
    aboveCell.lower[a] = split;
    const float splitCost =
        kTraversalCost + kIntersectionCost / area *
                             (belowCell.area() * static_cast<float>(belowCount) +
                              aboveCell.area() * static_cast<float>(aboveCount));
    // A plane that leaves every triangle on both sides separates nothing; one that separates
    // hardly anything multiplies references (see kMaxCostRatio).
    if ((aboveCount == count && belowCount == count) ||
        !(splitCost < kMaxCostRatio * kIntersectionCost * static_cast<float>(count))) {
      makeLeaf(nodeIndex, begin, end, depth);
      return;
    }
    build(below, need, belowCell, depth + 1);
    tree_.nodes[nodeIndex] =
        KdNode::makeInner(a, split, static_cast<std::uint32_t>(tree_.nodes.size()));
    build(end, above, aboveCell, depth + 1);
  }

  /// Writes the references of refs_[begin, end) touching the closed cell above `split` to
  /// refs_[above...) and those touching the one below to refs_[...below), backwards. A triangle
  /// touching the plane, or lying in it, goes to both: the traversal must find a hit on the
  /// plane from either side. Testing the unclipped vertex range is the same as testing the box
  /// clipped to the cell, whose own bounds lie on either side of the split.
  template <int A>
  void partition(std::size_t begin, std::size_t end, float split, std::size_t& above,
                 std::size_t& below) {
    std::uint32_t* r = refs_.get();
    std::size_t up = above, down = below;
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t t = r[i];
      const TriangleVertices& tri = triangles_[t];
      const float x0 = coord<A>(tri.v0), x1 = coord<A>(tri.v1), x2 = coord<A>(tri.v2);
      // Both slots are written unconditionally and kept only when the triangle belongs there:
      // the sides of random triangles are unpredictable, and mispredicted branches would cost
      // more than the loads. The free gap [up, down) never closes before the loop ends.
      r[up] = t;
      up += (x0 >= split) | (x1 >= split) | (x2 >= split);
      r[down - 1] = t;
      down -= (x0 <= split) | (x1 <= split) | (x2 <= split);
    }
    above = up;
    below = down;
  }

  /// Makes refs_ hold at least `size` entries, keeping the live prefix.
  void reserveRefs(std::size_t size) {
    if (size <= refsCapacity_) return;
    const std::size_t capacity = std::max(size, 2 * refsCapacity_);
    auto grown = std::make_unique_for_overwrite<std::uint32_t[]>(capacity);
    if (refs_) std::copy(refs_.get(), refs_.get() + refsCapacity_, grown.get());
    refs_ = std::move(grown);
    refsCapacity_ = capacity;
  }

  void makeLeaf(std::uint32_t nodeIndex, std::size_t begin, std::size_t end, int depth) {
    const auto first = static_cast<std::uint32_t>(tree_.primIndices.size());
    const auto count = static_cast<std::uint32_t>(end - begin);
    tree_.primIndices.insert(tree_.primIndices.end(), refs_.get() + begin, refs_.get() + end);
    tree_.nodes[nodeIndex] = KdNode::makeLeaf(first, count);
    BuildStats& s = tree_.stats;
    ++s.leaves;
    if (count == 0) ++s.emptyLeaves;
    s.primReferences += count;
    s.maxDepth = std::max(s.maxDepth, static_cast<std::size_t>(depth));
  }

  const std::vector<TriangleVertices>& triangles_;
  FastKdTreeOptions options_;
  KdTree& tree_;
  int maxDepth_ = 0;
  std::unique_ptr<std::uint32_t[]> refs_;  ///< stack of reference lists (see build)
  std::size_t refsCapacity_ = 0;
};

}  // namespace

KdTree buildFastKdTree(const std::vector<TriangleVertices>& triangles,
                       const FastKdTreeOptions& options) {
  KdTree tree;
  FastBuilder(triangles, options, tree).run();
  return tree;
}

}  // namespace tg
