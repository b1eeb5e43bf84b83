// An index over one instance's material ranges (RenderScene::instanceMaterialRanges) that finds
// the range of a primitive in a load or two instead of a binary search. A scene graph merges
// the static meshes of a region into one object with a material range per source mesh (up to 73
// in a chunk of the BART kitchen); the binary search's chain of dependent loads was a third of
// preparing a hit for shading. Internal header: not installed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "tracegraph/backend/render/RenderScene.h"

namespace tg::detail {

/// Buckets of 2^shift primitives, each knowing the range that holds its first primitive; a
/// lookup starts there and steps forward over the ranges that begin inside the bucket.
class MaterialRangeIndex {
 public:
  using Ranges = std::vector<RenderScene::MaterialRange>;

  MaterialRangeIndex() = default;

  /// Indexes non-empty `ranges` sorted by primBegin (RenderScene::validate checks the order).
  explicit MaterialRangeIndex(const Ranges& ranges) {
    const std::uint64_t span = std::uint64_t(ranges.back().primBegin) + 1;
    // About four buckets per range: most buckets then lie inside one range.
    const std::uint64_t wanted = 4 * std::uint64_t(ranges.size());
    while ((span >> shift_) > wanted) ++shift_;
    const std::uint64_t buckets = ((span - 1) >> shift_) + 1;
    first_.resize(buckets);
    std::size_t k = 0;
    for (std::uint64_t b = 0; b < buckets; ++b) {
      k = stepTo(ranges, k, b << shift_);
      first_[b] = static_cast<std::uint32_t>(k);
    }
  }

  /// RenderScene::rangeContaining(ranges, primId) for the ranges this index was made from.
  std::size_t find(const Ranges& ranges, std::uint32_t primId) const {
    const std::size_t bucket = std::min<std::size_t>(primId >> shift_, first_.size() - 1);
    return stepTo(ranges, first_[bucket], primId);
  }

 private:
  /// From range k (which starts at or before `prim`, or is the first), the last range that
  /// starts at or before `prim`.
  static std::size_t stepTo(const Ranges& ranges, std::size_t k, std::uint64_t prim) {
    while (k + 1 < ranges.size() && ranges[k + 1].primBegin <= prim) ++k;
    return k;
  }

  std::vector<std::uint32_t> first_;
  unsigned shift_ = 0;
};

}  // namespace tg::detail
