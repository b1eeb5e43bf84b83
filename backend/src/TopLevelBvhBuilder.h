// The builder of the top-level BVH4 (TopLevelBvh), rebuilt over the instance boxes on every
// commit. Internal header: not installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "BvhBuilder.h"

namespace tg::detail {

/// Settings of a top-level build.
struct TopLevelBuildOptions {
  /// Bins of the SAH sweep along the widest centroid axis (at most kMaxBins).
  int bins = 16;
  /// Largest leaf; bigger ranges are always split.
  std::uint32_t maxLeafSize = 2;
  /// SAH cost of visiting a node, relative to intersectionCost.
  float traversalCost = 1.0f;
  /// SAH cost of entering one instance.
  float intersectionCost = 4.0f;
  /// Ranges with more primitives bin and partition in parallel, and their subtrees are built
  /// as parallel tasks.
  std::size_t parallelThreshold = 8192;

  /// Largest supported bin count.
  static constexpr int kMaxBins = 32;
};

/// Binned-SAH BVH4 construction for trees rebuilt every frame: the splits of buildBvh4 with one
/// binned axis (BvhBuildOptions::allAxes false), so the same tree, at a fraction of its cost.
///
/// Each bin also keeps the bounds of its centroids, so the bounds of both sides of a split come
/// from the bins, and the partition only moves primitives. Large ranges bin in fixed blocks in
/// parallel and partition in parallel from the blocks' counts; blocks depend on the range
/// alone, so the tree is the same whatever the number of threads (only node numbering may
/// differ). The builder keeps its scratch between builds.
class TopLevelBvhBuilder {
 public:
  /// Builds over `prims` and reorders them so that every leaf's primitives are contiguous: a
  /// leaf slot (child, count) refers to prims[child, child + count). `out.nodes` keeps its
  /// capacity between builds. Fills every field of `out` but sahCost (left negative).
  void build(BvhPrimArray& prims, const TopLevelBuildOptions& options, BvhBuildResult& out);

  /// Bytes held by the buffers kept between builds.
  std::size_t scratchBytes() const { return scratch_.capacity() * sizeof(BvhPrim); }

 private:
  BvhPrimArray scratch_;  ///< target of the parallel partition
};

}  // namespace tg::detail
