// Morton-code BVH4 construction: centroid codes, a stable radix sort, and a top-down split of
// the sorted codes at their highest differing bit, four ranges per node.
#include "BvhMortonBuilder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <bit>
#include <limits>

#include "Bvh4Refit.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#define TG_MORTON_SSE 1
#else
#define TG_MORTON_SSE 0
#endif

namespace tg::detail {
namespace {

/// Loops over fewer elements run on the calling thread: below this, scheduling tasks costs
/// more than it saves.
constexpr std::size_t kParallelElements = 16384;
/// The radix sort cuts inputs into at most this many blocks of at least kSortBlockKeys keys.
/// The cut depends only on the input size, and the sort is stable whatever the cut, so the
/// order never depends on the thread count. More blocks than threads let a thread that gets
/// the core back late leave its share to the others.
constexpr std::size_t kMaxSortBlocks = 8;
constexpr std::size_t kSortBlockKeys = 4096;
/// Bits per radix digit: three passes cover the 30-bit codes, stored above the 32-bit index.
constexpr int kDigitBits = 10;
constexpr std::size_t kDigits = std::size_t{1} << kDigitBits;
/// Quantisation cells per axis (10 bits each).
constexpr float kCells = 1024.0f;

template <class Fn>
void forRange(std::size_t n, Fn&& fn) {
  if (n < kParallelElements) {
    fn(std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); });
}

/// Spreads the low 10 bits of v so that two zero bits follow each.
inline std::uint32_t spreadBits(std::uint32_t v) {
  v &= 0x3FFu;
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

/// Cell of a centroid coordinate. Clamping in float first keeps the conversion defined for any
/// input: a NaN (the centroid of an empty box) or an overflowing product lands in cell 0 or the
/// last cell.
inline std::uint32_t cellOf(float c, float lower, float scale) {
  float f = (c - lower) * scale;
  f = f > 0.0f ? f : 0.0f;
  f = f < kCells - 1.0f ? f : kCells - 1.0f;
  return static_cast<std::uint32_t>(f);
}

#if TG_MORTON_SSE
/// spreadBits of four cells, by shifts (SSE2 has no 32-bit multiply); same bits.
inline __m128i spreadBits4(__m128i v) {
  v = _mm_and_si128(_mm_or_si128(v, _mm_slli_epi32(v, 16)), _mm_set1_epi32(0x030000FF));
  v = _mm_and_si128(_mm_or_si128(v, _mm_slli_epi32(v, 8)), _mm_set1_epi32(0x0300F00F));
  v = _mm_and_si128(_mm_or_si128(v, _mm_slli_epi32(v, 4)), _mm_set1_epi32(0x030C30C3));
  v = _mm_and_si128(_mm_or_si128(v, _mm_slli_epi32(v, 2)), _mm_set1_epi32(0x09249249));
  return v;
}

/// The keys of centroids [begin, end) four at a time, rounded exactly like cellOf (max and min
/// return their second operand for a NaN, as cellOf's comparisons do); returns where the
/// scalar loop must take over.
std::size_t mortonKeysSse(const Vec3f* centroids, std::size_t begin, std::size_t end,
                          const float lower[3], const float scale[3], std::uint64_t* keys) {
  const __m128 zero = _mm_setzero_ps(), last = _mm_set1_ps(kCells - 1.0f);
  __m128 lo[3], sc[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = _mm_set1_ps(lower[a]);
    sc[a] = _mm_set1_ps(scale[a]);
  }
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    __m128i code = _mm_setzero_si128();
    for (int a = 0; a < 3; ++a) {
      const __m128 c = _mm_setr_ps(centroids[i][a], centroids[i + 1][a], centroids[i + 2][a],
                                   centroids[i + 3][a]);
      __m128 f = _mm_mul_ps(_mm_sub_ps(c, lo[a]), sc[a]);
      f = _mm_min_ps(_mm_max_ps(f, zero), last);
      code = _mm_or_si128(code, _mm_slli_epi32(spreadBits4(_mm_cvttps_epi32(f)), 2 - a));
    }
    const __m128i index = _mm_setr_epi32(static_cast<int>(i), static_cast<int>(i + 1),
                                         static_cast<int>(i + 2), static_cast<int>(i + 3));
    // (code << 32) | index, little-endian: the index is the low word of each key.
    _mm_storeu_si128(reinterpret_cast<__m128i*>(keys + i), _mm_unpacklo_epi32(index, code));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(keys + i + 2), _mm_unpackhi_epi32(index, code));
  }
  return i;
}
#endif

/// Where a range splits: the first code with the highest bit in which the range's codes differ,
/// or the middle when all codes are equal (which halves the range, so equal codes add at most
/// log2(n) levels).
std::uint32_t splitMortonRange(const std::uint32_t* codes, MortonRange r) {
  const std::uint32_t first = codes[r.begin], last = codes[r.end - 1];
  if (first == last) return r.begin + r.count() / 2;
  const std::uint32_t bit = std::uint32_t{1} << (std::bit_width(first ^ last) - 1);
  // The codes share every bit above `bit`, so those with it clear come first. codes[begin] has
  // it clear and codes[end - 1] set: the split lies in [begin + 1, end - 1]. Branch-free
  // bisection: the direction of each step is a coin toss the branch predictor cannot learn,
  // and a conditional move costs less than the mispredictions.
  const std::uint32_t* base = codes + r.begin;
  std::uint32_t len = r.count();
  while (len > 1) {
    const std::uint32_t half = len / 2;
    base = (base[half] & bit) ? base : base + half;
    len -= half;
  }
  return static_cast<std::uint32_t>(base - codes) + 1;
}

}  // namespace

int openMortonRanges(const std::uint32_t* codes, MortonRange range, std::uint32_t maxLeaf,
                     MortonRange ranges[4]) {
  // Like the SAH builder's widest child first, opening the largest cell keeps big boxes from
  // sharing a node with small ones. Every child range is at least one binary level below this
  // node's, so the BVH4 is no deeper than the binary tree.
  ranges[0] = range;
  int n = 1;
  while (n < 4) {
    int largest = -1;
    std::uint64_t largestKey = 0;
    for (int c = 0; c < n; ++c) {
      if (ranges[c].count() <= maxLeaf) continue;
      const std::uint64_t key =
          (std::uint64_t{codes[ranges[c].begin] ^ codes[ranges[c].end - 1]} << 32) |
          ranges[c].count();
      if (key > largestKey) {
        largestKey = key;
        largest = c;
      }
    }
    if (largest < 0) break;
    const MortonRange parent = ranges[largest];
    const std::uint32_t mid = splitMortonRange(codes, parent);
    // Keep the slots in code order: neighbours on the curve stay neighbours in memory.
    for (int c = n; c > largest + 1; --c) ranges[c] = ranges[c - 1];
    ranges[largest] = {parent.begin, mid};
    ranges[largest + 1] = {mid, parent.end};
    ++n;
  }
  return n;
}

void BvhMortonBuilder::build(std::span<const Box3f> boxes, const BvhMortonOptions& options,
                             std::vector<std::uint32_t>& order, BvhBuildResult& out) {
  const std::size_t n = boxes.size();
  centroids_.resize(n);
  forRange(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) centroids_[i] = boxes[i].lower + boxes[i].upper;
  });
  sort(centroids_, order);
  NoLeafData none;
  emit(
      options,
      [&](std::uint32_t first, std::uint32_t count, NoLeafData&) {
        Box3f box;
        for (std::uint32_t k = first; k < first + count; ++k) box.extend(boxes[order[k]]);
        return box;
      },
      out, none);
}

void BvhMortonBuilder::sort(std::span<const Vec3f> centroids, std::vector<std::uint32_t>& order,
                            const MortonCentroidBounds* bounds, std::uint32_t* rank) {
  const std::size_t n = centroids.size();
  order.resize(n);
  codes_.resize(n);
  if (n == 0) return;
  computeKeys(centroids, bounds);
  sortKeys();
  forRange(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t index = static_cast<std::uint32_t>(keys_[k]);
      order[k] = index;
      codes_[k] = static_cast<std::uint32_t>(keys_[k] >> 32);
      if (rank != nullptr) rank[index] = static_cast<std::uint32_t>(k);
    }
  });
}

void BvhMortonBuilder::computeKeys(std::span<const Vec3f> centroids,
                                   const MortonCentroidBounds* bounds) {
  const std::size_t n = centroids.size();
  MortonCentroidBounds cb;
  if (bounds != nullptr) {
    cb = *bounds;
  } else if (n < kParallelElements) {
    for (const Vec3f& c : centroids) cb.add(c);
  } else {
    cb = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, 4096), MortonCentroidBounds{},
        [&](const tbb::blocked_range<std::size_t>& r, MortonCentroidBounds acc) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) acc.add(centroids[i]);
          return acc;
        },
        [](MortonCentroidBounds a, const MortonCentroidBounds& b) {
          a.merge(b);
          return a;
        });
  }
  float scale[3];
  for (int a = 0; a < 3; ++a) {
    // No extent (all centroids in one plane), no finite centroid or an overflowing extent:
    // the axis contributes nothing to the code.
    const float extent = cb.upper[a] - cb.lower[a];
    scale[a] = extent > 0.0f && extent < MortonCentroidBounds::kInf ? kCells / extent : 0.0f;
  }
  keys_.resize(n);
  forRange(n, [&](std::size_t begin, std::size_t end) {
    std::size_t i = begin;
#if TG_MORTON_SSE
    i = mortonKeysSse(centroids.data(), begin, end, cb.lower, scale, keys_.data());
#endif
    for (; i < end; ++i) {
      std::uint32_t code = 0;
      for (int a = 0; a < 3; ++a) {
        const std::uint32_t cell = cellOf(centroids[i][a], cb.lower[a], scale[a]);
        code |= spreadBits(cell) << (2 - a);
      }
      keys_[i] = (std::uint64_t{code} << 32) | i;
    }
  });
}

void BvhMortonBuilder::sortKeys() {
  const std::size_t n = keys_.size();
  const std::size_t blocks = std::clamp<std::size_t>(n / kSortBlockKeys, 1, kMaxSortBlocks);
  const std::size_t blockSize = (n + blocks - 1) / blocks;
  scratch_.resize(n);
  histogram_.resize(blocks * kDigits);
  const auto forBlocks = [&](auto&& fn) {
    if (blocks == 1) {
      fn(std::size_t{0});
      return;
    }
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, blocks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t b = r.begin(); b != r.end(); ++b) fn(b);
        },
        tbb::simple_partitioner());
  };
  // Least significant digit first; each pass is stable (blocks in order, keys in order within a
  // block), so equal codes keep their index order.
  for (int shift = 32; shift < 32 + 30; shift += kDigitBits) {
    const std::uint64_t* src = keys_.data();
    std::uint64_t* dst = scratch_.data();
    forBlocks([&](std::size_t b) {
      std::uint32_t* h = histogram_.data() + b * kDigits;
      std::fill(h, h + kDigits, 0u);
      const std::size_t end = std::min(n, (b + 1) * blockSize);
      for (std::size_t i = b * blockSize; i < end; ++i) ++h[(src[i] >> shift) & (kDigits - 1)];
    });
    // A digit shared by every key (common for small or clustered inputs) moves nothing.
    bool trivial = false;
    for (std::size_t d = 0; d < kDigits && !trivial; ++d) {
      std::size_t total = 0;
      for (std::size_t b = 0; b < blocks; ++b) total += histogram_[b * kDigits + d];
      trivial = total == n;
      if (total != 0) break;
    }
    if (trivial) continue;
    // Exclusive offsets, digit-major then block order.
    std::uint32_t offset = 0;
    for (std::size_t d = 0; d < kDigits; ++d) {
      for (std::size_t b = 0; b < blocks; ++b) {
        std::uint32_t& h = histogram_[b * kDigits + d];
        const std::uint32_t count = h;
        h = offset;
        offset += count;
      }
    }
    forBlocks([&](std::size_t b) {
      std::uint32_t* h = histogram_.data() + b * kDigits;
      const std::size_t end = std::min(n, (b + 1) * blockSize);
      for (std::size_t i = b * blockSize; i < end; ++i)
        dst[h[(src[i] >> shift) & (kDigits - 1)]++] = src[i];
    });
    keys_.swap(scratch_);
  }
}

void buildBvh4Morton(BvhPrimArray& prims, const BvhBuildOptions& options, BvhBuildResult& out) {
  std::vector<Box3f> boxes(prims.size());
  for (std::size_t i = 0; i < prims.size(); ++i) boxes[i] = prims[i].box();
  BvhMortonOptions mortonOptions;
  mortonOptions.maxLeafSize = options.maxLeafSize;
  mortonOptions.parallelThreshold = options.parallelThreshold;
  mortonOptions.traversalCost = options.traversalCost;
  mortonOptions.intersectionCost = options.intersectionCost;
  std::vector<std::uint32_t> order;
  BvhMortonBuilder builder;
  builder.build(boxes, mortonOptions, order, out);
  BvhPrimArray sorted(prims.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = prims[order[k]];
  prims.swap(sorted);
}

}  // namespace tg::detail
