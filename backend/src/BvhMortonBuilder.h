// Linear (Morton-code) construction of 4-wide BVHs, for trees rebuilt every frame: the deforming
// object BVH (AccelKind::BvhFast). Internal header: not installed.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "BvhBuilder.h"
#include "BvhMortonEmit.h"

namespace tg::detail {

/// Settings of a Morton build.
struct BvhMortonOptions {
  /// Largest leaf; bigger ranges are always split.
  std::uint32_t maxLeafSize = 4;
  /// Ranges with more primitives are split on the calling thread; the subtrees below them are
  /// built as parallel jobs.
  std::size_t parallelThreshold = 4096;
  /// SAH weights of the cost figure the build reports (BvhBuildResult::sahCost).
  double traversalCost = 1.0;
  /// SAH cost of testing one primitive.
  double intersectionCost = 1.0;
};

/// Bounds of Morton centroids, written so that a NaN component (the centroid of an empty box)
/// leaves them as they are. Merging is exact, so any split of the work gives the same bounds.
struct MortonCentroidBounds {
  static constexpr float kInf = std::numeric_limits<float>::infinity();
  float lower[3] = {kInf, kInf, kInf};
  float upper[3] = {-kInf, -kInf, -kInf};

  /// Adds one centroid.
  void add(const Vec3f& c) {
    for (int a = 0; a < 3; ++a) {
      lower[a] = c[a] < lower[a] ? c[a] : lower[a];
      upper[a] = c[a] > upper[a] ? c[a] : upper[a];
    }
  }
  /// Adds the centroids of another bounds.
  void merge(const MortonCentroidBounds& o) {
    for (int a = 0; a < 3; ++a) {
      lower[a] = o.lower[a] < lower[a] ? o.lower[a] : lower[a];
      upper[a] = o.upper[a] > upper[a] ? o.upper[a] : upper[a];
    }
  }
};

/// Builds BVH4s after Karras 2012 ("Maximizing parallelism in the construction of BVHs, octrees
/// and k-d trees"): primitives are sorted by the 30-bit Morton code of their centroid within
/// the centroid bounds, and every sorted range splits where the highest differing code bit
/// changes (the binary radix tree), built top-down so that each BVH4 node takes four ranges at
/// once by opening its largest child range again. Ranges of equal codes split at the middle,
/// which bounds the depth to 30 + log2(n) binary levels, below kBvh4MaxDepth for any 32-bit
/// primitive count. Boxes are made on the way back up the same recursion (MortonEmitter), from
/// the caller's leaf boxes, so that no second walk over the nodes is needed.
///
/// Several times cheaper than binned SAH (a sort and one pass over the tree) at the price of
/// somewhat looser trees. The tree depends only on the centroids: the sort is stable (equal
/// codes keep their input order) and subtrees are split the same way whatever the number of
/// threads, into the same node numbering. The builder keeps its buffers between builds, so
/// per-frame rebuilds do not allocate once the primitive count has stopped growing.
class BvhMortonBuilder {
 public:
  /// Builds over `boxes`, one per primitive (empty boxes are allowed: they sort as if at the
  /// centroid bounds' minimum corner and never widen a node). `order` receives the primitive
  /// indices in leaf order: a leaf slot (first, count) refers to primitives order[first, first +
  /// count). `out.nodes` and `order` keep their capacity between builds. Also fills
  /// `out.sahCost`.
  void build(std::span<const Box3f> boxes, const BvhMortonOptions& options,
             std::vector<std::uint32_t>& order, BvhBuildResult& out);

  /// First half of a build: sorts the primitives by the Morton code of their centroid (any
  /// fixed multiple of the centre will do; NaN components sort as the minimum). `order`
  /// receives the primitive indices in leaf order. `bounds`, when given, must be the bounds of
  /// `centroids` (a caller that makes the centroids can gather them in the same pass); `rank`,
  /// when given, receives the leaf position of every primitive (rank[order[k]] = k).
  void sort(std::span<const Vec3f> centroids, std::vector<std::uint32_t>& order,
            const MortonCentroidBounds* bounds = nullptr, std::uint32_t* rank = nullptr);

  /// Second half: the nodes over the primitives sorted by the last sort(), with their boxes.
  /// `leafBox(first, count, acc)` returns the box of the primitives order[first, first + count)
  /// and may gather more into `acc` (as refitBvh4's leafBox; it is called from several threads
  /// at once, each with its own Acc, merged in a fixed order). Fills every field of `out`.
  template <class Acc, class LeafBox>
  void emit(const BvhMortonOptions& options, const LeafBox& leafBox, BvhBuildResult& out,
            Acc& acc) {
    MortonEmitter<Acc, LeafBox> emitter(codes_.data(), options.maxLeafSize, options.traversalCost,
                                        options.intersectionCost, leafBox);
    const std::size_t n = codes_.size();
    // Above the threshold, jobs of about n / kEmitJobs primitives: enough of them for the
    // threads to even out, whatever the size. Depends on n only, like the tree.
    const std::size_t jobSize =
        n <= options.parallelThreshold
            ? options.parallelThreshold
            : std::min(options.parallelThreshold, std::max(n / kEmitJobs, kMinEmitJob));
    emitter.run(static_cast<std::uint32_t>(n), jobSize, emit_, out, acc);
  }

  /// Bytes held by the buffers kept between builds.
  std::size_t scratchBytes() const {
    return centroids_.capacity() * sizeof(Vec3f) +
           (keys_.capacity() + scratch_.capacity()) * sizeof(std::uint64_t) +
           (codes_.capacity() + histogram_.capacity()) * sizeof(std::uint32_t) + emit_.bytes();
  }

 private:
  static constexpr std::size_t kEmitJobs = 32;     ///< jobs aimed at by emit()
  static constexpr std::size_t kMinEmitJob = 256;  ///< smallest job size emit() picks

  /// Centroid bounds, then one (code << 32 | index) key per centroid into keys_.
  void computeKeys(std::span<const Vec3f> centroids, const MortonCentroidBounds* bounds);
  /// Stable LSD radix sort of keys_ by code.
  void sortKeys();

  std::vector<Vec3f> centroids_;          ///< build(): box centroids (lower + upper)
  std::vector<std::uint64_t> keys_;       ///< (Morton code << 32) | primitive index
  std::vector<std::uint64_t> scratch_;    ///< radix sort ping-pong buffer
  std::vector<std::uint32_t> codes_;      ///< sorted Morton codes
  std::vector<std::uint32_t> histogram_;  ///< per-block digit counts of the radix sort
  MortonEmitScratch emit_;                ///< node buffers of the parallel emission
};

/// buildBvh4's contract (prims reordered into leaf order, leaf slots index prims) with the
/// Morton builder; of `options` only maxLeafSize, parallelThreshold and the SAH weights apply.
/// Allocates its scratch on every call: for tests and one-off builds.
void buildBvh4Morton(BvhPrimArray& prims, const BvhBuildOptions& options, BvhBuildResult& out);

}  // namespace tg::detail
