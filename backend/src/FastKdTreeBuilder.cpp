// The paper's fast kd-tree builder for deforming objects: spatial-median splits in the dimension
// of largest cell extent, triangles classified by their bounding boxes, and a leaf tolerance that
// grows with depth. A tree is rebuilt every frame, so build speed matters more than the last few
// percent of traversal speed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/KdTree.h"

namespace tg {
namespace {

/// A triangle's bounding box, laid out for indexing by axis.
struct TriangleBox {
  float lower[3];
  float upper[3];
};

class FastBuilder {
 public:
  FastBuilder(const std::vector<TriangleVertices>& triangles, const FastKdTreeOptions& options,
              KdTree& tree)
      : triangles_(triangles), options_(options), tree_(tree) {}

  void run() {
    const std::size_t n = triangles_.size();
    if (n > kKdMaxLeafCount) throw Error("buildFastKdTree: more than 2^30 - 1 triangles");
    boxes_.resize(n);
    refs_.clear();
    refs_.reserve(4 * n + 16);
    Box3f bounds;
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleVertices& t = triangles_[i];
      if (isDegenerateTriangle(t.v0, t.v1, t.v2)) {
        ++tree_.stats.degenerate;
        continue;
      }
      const Vec3f lo = min(min(t.v0, t.v1), t.v2), hi = max(max(t.v0, t.v1), t.v2);
      boxes_[i] = {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
      bounds.extend(Box3f(lo, hi));
      refs_.push_back(static_cast<std::uint32_t>(i));
    }
    tree_.bounds = bounds;
    const std::size_t count = refs_.size();
    maxDepth_ = options_.maxDepth > 0
                    ? std::min(options_.maxDepth, kKdMaxDepth)
                    : std::min(kKdMaxDepth,
                               static_cast<int>(2.0 * std::log2(std::max<double>(
                                                          1.0, static_cast<double>(count))) +
                                                4.0));
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
    const float tolerance = static_cast<float>(options_.leafSize) +
                            options_.leafSizeGrowth * static_cast<float>(depth);
    if (static_cast<float>(count) <= tolerance || depth >= maxDepth_) {
      makeLeaf(nodeIndex, begin, end, depth);
      return;
    }
    const int a = maxDimension(cell.extent());
    const float lo = cell.lower[a], hi = cell.upper[a];
    // Halving each end first cannot overflow; the clamp guards the closed cell against rounding.
    const float split = std::clamp(0.5f * lo + 0.5f * hi, lo, hi);

    const std::size_t need = end + 2 * count;
    if (refs_.size() < need) refs_.resize(std::max(need, 2 * refs_.size()));
    std::uint32_t* r = refs_.data();
    std::size_t above = end, below = need;
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t t = r[i];
      const TriangleBox& b = boxes_[t];
      // The cell's own bounds lie on either side of the split, so testing the unclipped box is
      // the same as testing the box clipped to the cell. Touching the plane counts: a triangle
      // lying in it goes to both children.
      r[above] = t;
      above += b.upper[a] >= split;
      if (b.lower[a] <= split) r[--below] = t;
    }
    const std::size_t aboveCount = above - end, belowCount = need - below;
    if (aboveCount == count && belowCount == count) {
      // The plane separates nothing; splitting further would only duplicate references.
      makeLeaf(nodeIndex, begin, end, depth);
      return;
    }
    Box3f belowCell = cell, aboveCell = cell;
    belowCell.upper[a] = split;
    aboveCell.lower[a] = split;
    build(below, need, belowCell, depth + 1);
    tree_.nodes[nodeIndex] =
        KdNode::makeInner(a, split, static_cast<std::uint32_t>(tree_.nodes.size()));
    build(end, above, aboveCell, depth + 1);
  }

  void makeLeaf(std::uint32_t nodeIndex, std::size_t begin, std::size_t end, int depth) {
    const auto first = static_cast<std::uint32_t>(tree_.primIndices.size());
    const auto count = static_cast<std::uint32_t>(end - begin);
    tree_.primIndices.insert(tree_.primIndices.end(),
                             refs_.begin() + static_cast<std::ptrdiff_t>(begin),
                             refs_.begin() + static_cast<std::ptrdiff_t>(end));
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
  std::vector<TriangleBox> boxes_;    ///< per triangle id
  std::vector<std::uint32_t> refs_;   ///< stack of reference lists (see build)
};

}  // namespace

KdTree buildFastKdTree(const std::vector<TriangleVertices>& triangles,
                       const FastKdTreeOptions& options) {
  KdTree tree;
  FastBuilder(triangles, options, tree).run();
  return tree;
}

}  // namespace tg
