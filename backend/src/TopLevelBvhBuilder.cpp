// Top-level BVH4 construction: binned SAH on the widest centroid axis, four-wide nodes built
// directly by opening the widest child range until a node has four (as buildBvh4 does).
//
// What makes it cheaper than the general builder on a per-frame rebuild: a range is binned and
// partitioned as soon as it is created, and each bin keeps the bounds of its boxes and of their
// centroids, so both sides of the split get their bounds from the bins. The partition then only
// moves primitives instead of gathering four boxes per primitive. Large ranges bin in fixed
// blocks in parallel, and the blocks' counts give every block its place in a parallel
// partition, so the top levels are not a serial pass each.
#include "TopLevelBvhBuilder.h"

#include "BvhBinning.h"

#include <emmintrin.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace tg::detail {
namespace {

/// BVH4 levels below which splits are object medians whatever the SAH says (as in buildBvh4):
/// a median halves a range, which bounds the depth however skewed the input is.
constexpr int kMedianDepth = 32;

/// Primitives per block of a parallel binning and partition. Fixed, so that the blocks depend
/// on the range alone and not on the number of threads.
constexpr std::size_t kBlock = 2048;

/// Ranges with at least this many primitives bin into two alternating bin sets: neighbouring
/// primitives often fall into the same bin, and each update would wait for the previous one.
constexpr std::size_t kInterleaveMin = 64;

/// Ranges of at most this many primitives are split without bins (Builder::splitSmall).
constexpr int kSmall = 16;

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A box in two SSE registers (lane 3 unused). Left uninitialised by default: ranges and bins
/// are made by the million per second, and most are written before they are read.
struct Box4 {
  __m128 lower;
  __m128 upper;

  static Box4 empty() { return {_mm_set1_ps(kInf), _mm_set1_ps(-kInf)}; }
  void extend(__m128 lo, __m128 hi) {
    lower = _mm_min_ps(lower, lo);
    upper = _mm_max_ps(upper, hi);
  }
  void extend(const Box4& b) { extend(b.lower, b.upper); }
  /// The box as a Box3f.
  Box3f box() const { return SseBox{lower, upper}.box(); }
  /// Surface area as SseBox::area computes it, so that both builders weigh splits alike.
  float area() const { return SseBox{lower, upper}.area(); }
};

/// A contiguous range of primitives with its bounds and the bounds of its centroids (stored as
/// lower + upper: twice the centre, which orders the same).
struct Range {
  std::size_t begin = 0, end = 0;
  Box4 bounds, centroids;
  std::size_t count() const { return end - begin; }
};

/// The bin mapping of one range on its binned axis.
struct Mapping {
  int axis = 0;
  int bins = 0;
  float origin = 0.0f;
  float scale = 0.0f;
  int of(const BvhPrim& p) const {
    return binOf(p.lower[axis] + p.upper[axis], origin, scale, bins);
  }
};

/// Boxes, centroid bounds and counts of the bins of one range on its binned axis. Only the
/// first `used` bins are initialised.
struct Bins {
  struct Bin {
    Box4 box, centroids;
  };
  /// Not initialised: reset() empties the bins a range uses.
  Bin bin[TopLevelBuildOptions::kMaxBins];
  std::uint32_t count[TopLevelBuildOptions::kMaxBins];
  int used = 0;

  void reset(int bins) {
    used = bins;
    for (int b = 0; b < bins; ++b) {
      bin[b].box = Box4::empty();
      bin[b].centroids = Box4::empty();
      count[b] = 0;
    }
  }
  void add(const BvhPrim& p, int b) {
    const __m128 lo = primLower(p), hi = primUpper(p);
    const __m128 c = _mm_add_ps(lo, hi);
    bin[b].box.extend(lo, hi);
    bin[b].centroids.extend(c, c);
    ++count[b];
  }
  void add(const BvhPrim* prims, std::size_t begin, std::size_t end, const Mapping& map) {
    for (std::size_t i = begin; i < end; ++i) add(prims[i], map.of(prims[i]));
  }
  void merge(const Bins& o) {
    for (int b = 0; b < used; ++b) {
      bin[b].box.extend(o.bin[b].box);
      bin[b].centroids.extend(o.bin[b].centroids);
      count[b] += o.count[b];
    }
  }
  /// Primitives in bins [0, split).
  std::size_t countBelow(int split) const {
    std::size_t n = 0;
    for (int b = 0; b < split; ++b) n += count[b];
    return n;
  }
};

/// The cheapest plane of a binned range: primitives in bins [0, bin) go left. bin < 0 when no
/// plane separates two non-empty sides. Costs are taken as buildBvh4's sweep takes them, and
/// ties go to the lower bin.
struct BinSplit {
  int bin = -1;
  float cost = kInf;
};

BinSplit sweep(const Bins& bins) {
  BinSplit best;
  const int n = bins.used;
  float rightCost[TopLevelBuildOptions::kMaxBins];  // written for bins [1, n) below
  Box4 acc = Box4::empty();
  std::uint32_t count = 0;
  for (int b = n - 1; b > 0; --b) {
    acc.extend(bins.bin[b].box);
    count += bins.count[b];
    rightCost[b] = count == 0 ? -1.0f : acc.area() * static_cast<float>(count);
  }
  acc = Box4::empty();
  count = 0;
  for (int b = 1; b < n; ++b) {
    acc.extend(bins.bin[b - 1].box);
    count += bins.count[b - 1];
    if (count == 0 || rightCost[b] < 0.0f) continue;
    const float cost = acc.area() * static_cast<float>(count) + rightCost[b];
    if (cost < best.cost) {
      best.cost = cost;
      best.bin = b;
    }
  }
  return best;
}

/// Centroid coordinate as a key that orders NaN after everything, so that the median
/// comparison stays a strict weak order on any input.
inline float medianKey(const BvhPrim& p, int axis) {
  const float c = p.lower[axis] + p.upper[axis];
  return std::isnan(c) ? kInf : c;
}

class Builder {
 public:
  Builder(BvhPrimArray& prims, BvhPrimArray& scratch, const TopLevelBuildOptions& options,
          BvhBuildResult& out)
      : prims_(prims),
        scratch_(scratch),
        options_(options),
        bins_(std::clamp(options.bins, 2, TopLevelBuildOptions::kMaxBins)),
        out_(out) {}

  void build() {
    out_.leaves = 0;
    out_.maxDepth = 0;
    out_.bounds = Box3f{};
    out_.sahCost = -1.0;
    if (prims_.empty()) {
      out_.nodes.clear();
      return;
    }
    if (prims_.size() > options_.parallelThreshold && scratch_.size() < prims_.size())
      scratch_.resize(prims_.size());
    const Range root = makeRange(0, prims_.size());
    out_.bounds = root.bounds.box();
    // Every inner node has at least two children, except a root that is a single leaf, so
    // there are at most as many nodes as primitives.
    out_.nodes.resize(prims_.size());
    nextNode_.store(1, std::memory_order_relaxed);
    Child top;
    makeChild(top, root, 0);
    if (top.leaf) {
      Bvh4Node& node = out_.nodes[0];
      node = Bvh4Node::makeEmpty();
      node.setBounds(0, root.bounds.box());
      node.child[0] = 0;
      node.count[0] = static_cast<std::uint32_t>(root.count());
      out_.leaves = 1;
    } else {
      const Counts counts = buildNode(0, top, 0);
      out_.leaves = counts.leaves;
      out_.maxDepth = counts.maxDepth;
    }
    out_.nodes.resize(nextNode_.load(std::memory_order_relaxed));
  }

 private:
  /// A child range under construction: a leaf, or already split into `left` and `right`.
  struct Child {
    Range range;
    bool leaf;
    Range left, right;  ///< set when not a leaf
  };

  /// Makes `c` the child range `r` at BVH4 level `depth`, in place: a Child returned by value
  /// would be copied in 16-byte moves right after its one-byte leaf flag was stored, and such
  /// a load waits for the store instead of being forwarded from it.
  void makeChild(Child& c, const Range& r, int depth) {
    c.range = r;
    c.leaf = !split(r, depth, c.left, c.right);
  }

  /// Bounds and centroid bounds of prims[begin, end), in parallel blocks when it is large
  /// (min and max are exact, so the blocks do not change the result).
  Range makeRange(std::size_t begin, std::size_t end) const {
    const auto gather = [this](std::size_t b, std::size_t e, Box4& bounds, Box4& centroids) {
      for (std::size_t i = b; i < e; ++i) {
        const __m128 lo = primLower(prims_[i]), hi = primUpper(prims_[i]);
        bounds.extend(lo, hi);
        const __m128 c = _mm_add_ps(lo, hi);
        centroids.extend(c, c);
      }
    };
    Range r{begin, end, Box4::empty(), Box4::empty()};
    const std::size_t n = end - begin;
    if (n <= options_.parallelThreshold) {
      gather(begin, end, r.bounds, r.centroids);
      return r;
    }
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<Box4> parts(2 * blocks, Box4::empty());
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t k) {
      gather(begin + k * kBlock, std::min(end, begin + (k + 1) * kBlock), parts[2 * k],
             parts[2 * k + 1]);
    });
    for (std::size_t k = 0; k < blocks; ++k) {
      r.bounds.extend(parts[2 * k]);
      r.centroids.extend(parts[2 * k + 1]);
    }
    return r;
  }

  /// Decides how `r` (a child at BVH4 level `depth`) is split and applies it at once: true
  /// with the two sides in `left` and `right`, false when `r` stays a leaf.
  bool split(const Range& r, int depth, Range& left, Range& right) {
    const std::size_t n = r.count();
    if (n <= 1) return false;
    const bool mayBeLeaf = n <= options_.maxLeafSize;
    const Box3f centroids = r.centroids.box();
    const Vec3f extent = centroids.extent();
    const int axis = maxDimension(extent);
    // Deep ranges, and ranges whose centroids all coincide (e.g. instances at one place):
    // no plane separates them, or the depth bound takes over.
    if (depth >= kMedianDepth || !(extent[axis] > 0.0f)) {
      if (mayBeLeaf) return false;
      splitMedian(r, axis, left, right);
      return true;
    }
    Mapping map;
    map.axis = axis;
    // More bins than primitives only adds empty bins to sweep.
    map.bins = std::min(bins_, static_cast<int>(std::max<std::size_t>(n, 4)));
    map.origin = centroids.lower[axis];
    // Slightly fewer than `bins` bins per extent, so the largest centroid stays in the last bin
    // after rounding.
    map.scale = static_cast<float>(map.bins) * 0.99999f / extent[axis];

    if (n > options_.parallelThreshold) return splitParallel(r, map, mayBeLeaf, left, right);
    if (n <= kSmall) return splitSmall(r, map, mayBeLeaf, left, right);

    const BvhPrim* p = prims_.data();
    Bins bins;
    bins.reset(map.bins);
    if (n >= kInterleaveMin) {
      Bins odd;
      odd.reset(map.bins);
      std::size_t i = r.begin;
      for (; i + 1 < r.end; i += 2) {
        bins.add(p[i], map.of(p[i]));
        odd.add(p[i + 1], map.of(p[i + 1]));
      }
      if (i < r.end) bins.add(p[i], map.of(p[i]));
      bins.merge(odd);
    } else {
      bins.add(p, r.begin, r.end, map);
    }
    const BinSplit found = sweep(bins);
    if (found.bin < 0 || (mayBeLeaf && leafIsCheaper(r, n, found))) {
      if (mayBeLeaf) return false;
      splitMedian(r, axis, left, right);
      return true;
    }
    sides(r, bins, found.bin, left, right);
    partitionSerial(r, map, found.bin);
    return true;
  }

  /// split() for a range of at most kSmall primitives, which most ranges are: the primitives
  /// are ordered by bin, and the sweep runs over them instead of over bins. The costs are the
  /// bins' costs (a plane between two occupied bins costs the same wherever it lies in the
  /// empty bins between them, and the lowest such plane is the one after the left side's last
  /// bin), so the split is the one the binned sweep picks.
  bool splitSmall(const Range& r, const Mapping& map, bool mayBeLeaf, Range& left, Range& right) {
    BvhPrim* p = prims_.data() + r.begin;
    const int n = static_cast<int>(r.count());
    int bin[kSmall];
    for (int i = 0; i < n; ++i) bin[i] = map.of(p[i]);
    // Stable insertion sort by bin, moving 16-byte halves.
    for (int i = 1; i < n; ++i) {
      const int b = bin[i];
      const __m128 lo = _mm_load_ps(p[i].lower), hi = _mm_load_ps(p[i].upper);
      int k = i;
      for (; k > 0 && bin[k - 1] > b; --k) {
        bin[k] = bin[k - 1];
        _mm_store_ps(p[k].lower, _mm_load_ps(p[k - 1].lower));
        _mm_store_ps(p[k].upper, _mm_load_ps(p[k - 1].upper));
      }
      bin[k] = b;
      _mm_store_ps(p[k].lower, lo);
      _mm_store_ps(p[k].upper, hi);
    }
    // Suffix boxes: what lies right of a plane before primitive k.
    Box4 suffix[kSmall + 1];
    Box4 suffixCentroids[kSmall + 1];
    suffix[n] = suffixCentroids[n] = Box4::empty();
    for (int k = n - 1; k >= 0; --k) {
      const __m128 lo = primLower(p[k]), hi = primUpper(p[k]);
      const __m128 c = _mm_add_ps(lo, hi);
      suffix[k] = suffix[k + 1];
      suffix[k].extend(lo, hi);
      suffixCentroids[k] = suffixCentroids[k + 1];
      suffixCentroids[k].extend(c, c);
    }
    BinSplit found;
    int at = -1;
    Box4 prefix = Box4::empty();
    for (int k = 1; k < n; ++k) {
      prefix.extend(primLower(p[k - 1]), primUpper(p[k - 1]));
      if (bin[k - 1] == bin[k]) continue;  // no plane between primitives of one bin
      const float cost =
          prefix.area() * static_cast<float>(k) + suffix[k].area() * static_cast<float>(n - k);
      if (cost < found.cost) {
        found.cost = cost;
        found.bin = bin[k - 1] + 1;
        at = k;
      }
    }
    if (at < 0 || (mayBeLeaf && leafIsCheaper(r, r.count(), found))) {
      if (mayBeLeaf) return false;
      splitMedian(r, map.axis, left, right);
      return true;
    }
    left.begin = r.begin;
    left.end = right.begin = r.begin + static_cast<std::size_t>(at);
    right.end = r.end;
    left.bounds = left.centroids = Box4::empty();
    for (int k = 0; k < at; ++k) {
      const __m128 lo = primLower(p[k]), hi = primUpper(p[k]);
      const __m128 c = _mm_add_ps(lo, hi);
      left.bounds.extend(lo, hi);
      left.centroids.extend(c, c);
    }
    right.bounds = suffix[at];
    right.centroids = suffixCentroids[at];
    return true;
  }

  /// The SAH leaf test of a range small enough to be a leaf.
  bool leafIsCheaper(const Range& r, std::size_t n, const BinSplit& found) const {
    const double area = r.bounds.area();
    // A range without area (a point or a segment) gives the SAH nothing to weigh: small ones
    // stay leaves.
    if (!(area > 0.0)) return true;
    const double leafCost = double(options_.intersectionCost) * double(n);
    const double splitCost = double(options_.traversalCost) +
                             double(options_.intersectionCost) * double(found.cost) / area;
    return leafCost <= splitCost;
  }

  /// The two sides of `r` split before bin `bin`, with their bounds taken from the bins.
  static void sides(const Range& r, const Bins& bins, int bin, Range& left, Range& right) {
    left.bounds = left.centroids = right.bounds = right.centroids = Box4::empty();
    for (int b = 0; b < bins.used; ++b) {
      Range& side = b < bin ? left : right;
      side.bounds.extend(bins.bin[b].box);
      side.centroids.extend(bins.bin[b].centroids);
    }
    const std::size_t mid = r.begin + bins.countBelow(bin);
    left.begin = r.begin;
    left.end = mid;
    right.begin = mid;
    right.end = r.end;
  }

  /// Moves the primitives of bins [0, bin) to the front of `r`.
  void partitionSerial(const Range& r, const Mapping& map, int bin) {
    BvhPrim* p = prims_.data();
    // Branch-free Lomuto partition: sides are random at the top of the tree, so a partition
    // that branches on them mispredicts half of the time. [r.begin, mid) went left.
    // The swap moves 16-byte halves: std::swap copies a primitive field by field, and the next
    // iteration's 16-byte load of those fields then waits for the stores to retire instead of
    // being forwarded from them.
    std::size_t mid = r.begin;
    for (std::size_t i = r.begin; i < r.end; ++i) {
      const bool isLeft = map.of(p[i]) < bin;
      // Each half carries its id or padding lane along.
      const __m128 a0 = _mm_load_ps(p[i].lower), a1 = _mm_load_ps(p[i].upper);
      const __m128 b0 = _mm_load_ps(p[mid].lower), b1 = _mm_load_ps(p[mid].upper);
      _mm_store_ps(p[i].lower, b0);
      _mm_store_ps(p[i].upper, b1);
      _mm_store_ps(p[mid].lower, a0);
      _mm_store_ps(p[mid].upper, a1);
      mid += isLeft ? 1 : 0;
    }
  }

  /// split() for a large range: blocks of kBlock primitives bin in parallel, then each block
  /// scatters its primitives to the places its counts give it and the range is copied back.
  bool splitParallel(const Range& r, const Mapping& map, bool mayBeLeaf, Range& left,
                     Range& right) {
    const std::size_t n = r.count();
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    const auto blockBegin = [&](std::size_t k) { return r.begin + k * kBlock; };
    const auto blockEnd = [&](std::size_t k) {
      return std::min(r.end, r.begin + (k + 1) * kBlock);
    };
    std::vector<Bins> blockBins(blocks);
    const BvhPrim* p = prims_.data();
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t k) {
      Bins& bins = blockBins[k];
      bins.reset(map.bins);
      Bins odd;
      odd.reset(map.bins);
      std::size_t i = blockBegin(k);
      const std::size_t e = blockEnd(k);
      for (; i + 1 < e; i += 2) {
        bins.add(p[i], map.of(p[i]));
        odd.add(p[i + 1], map.of(p[i + 1]));
      }
      if (i < e) bins.add(p[i], map.of(p[i]));
      bins.merge(odd);
    });
    // Merged in block order; min, max and counts are exact, so any order gives the same bins.
    Bins all;
    all.reset(map.bins);
    for (const Bins& b : blockBins) all.merge(b);
    const BinSplit found = sweep(all);
    if (found.bin < 0 || (mayBeLeaf && leafIsCheaper(r, n, found))) {
      if (mayBeLeaf) return false;
      splitMedian(r, map.axis, left, right);
      return true;
    }
    sides(r, all, found.bin, left, right);
    // Where each block's primitives go: lefts in block order from r.begin, rights from mid.
    std::vector<std::size_t> leftAt(blocks), rightAt(blocks);
    std::size_t l = left.begin, rr = right.begin;
    for (std::size_t k = 0; k < blocks; ++k) {
      const std::size_t below = blockBins[k].countBelow(found.bin);
      leftAt[k] = l;
      rightAt[k] = rr;
      l += below;
      rr += (blockEnd(k) - blockBegin(k)) - below;
    }
    BvhPrim* q = scratch_.data();
    const int bin = found.bin;
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t k) {
      std::size_t li = leftAt[k], ri = rightAt[k];
      for (std::size_t i = blockBegin(k), e = blockEnd(k); i < e; ++i) {
        const bool isLeft = map.of(p[i]) < bin;
        q[isLeft ? li : ri] = p[i];
        li += isLeft ? 1 : 0;
        ri += isLeft ? 0 : 1;
      }
    });
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t k) {
      std::copy(q + blockBegin(k), q + blockEnd(k), prims_.data() + blockBegin(k));
    });
    return true;
  }

  /// Splits `r` at its median centroid on `axis`, ordered by centroid, then id, so that the
  /// halves do not depend on the input order of equal centroids.
  void splitMedian(const Range& r, int axis, Range& left, Range& right) {
    BvhPrim* p = prims_.data();
    const std::size_t mid = r.begin + r.count() / 2;
    std::nth_element(p + r.begin, p + mid, p + r.end, [axis](const BvhPrim& x, const BvhPrim& y) {
      const float cx = medianKey(x, axis), cy = medianKey(y, axis);
      return cx < cy || (cx == cy && x.id < y.id);
    });
    left = makeRange(r.begin, mid);
    right = makeRange(mid, r.end);
  }

  /// Leaf slots and deepest level of a subtree, summed on the way back up: shared atomic
  /// counters would cost a locked operation per node, contended between the threads.
  struct Counts {
    std::size_t leaves = 0;
    std::size_t maxDepth = 0;
    void merge(const Counts& o) {
      leaves += o.leaves;
      maxDepth = std::max(maxDepth, o.maxDepth);
    }
  };

  Counts buildNode(std::uint32_t index, const Child& first, int depth) {
    Child children[4];
    children[0] = first;
    int n = 1;
    while (n < 4) {
      // Open the widest child that is not a leaf: it is the one most rays would enter.
      int widest = -1;
      float widestArea = -1.0f;
      for (int c = 0; c < n; ++c) {
        if (children[c].leaf) continue;
        const float area = children[c].range.bounds.area();
        if (area > widestArea) {
          widestArea = area;
          widest = c;
        }
      }
      if (widest < 0) break;
      const Range left = children[widest].left, right = children[widest].right;
      makeChild(children[widest], left, depth + 1);
      makeChild(children[n++], right, depth + 1);
    }

    Bvh4Node& node = out_.nodes[index];
    // Slot boxes in two 4x4 transposes straight from the registers: lanes x, y, z of a slot's
    // corners become its column of the planes. Unused slots keep the empty box.
    __m128 lower[4], upper[4];
    for (int c = 0; c < 4; ++c) {
      const Box4 b = c < n ? children[c].range.bounds : Box4::empty();
      lower[c] = b.lower;
      upper[c] = b.upper;
    }
    _MM_TRANSPOSE4_PS(lower[0], lower[1], lower[2], lower[3]);
    _MM_TRANSPOSE4_PS(upper[0], upper[1], upper[2], upper[3]);
    for (int a = 0; a < 3; ++a) {
      _mm_store_ps(node.bounds[2 * a], lower[a]);
      _mm_store_ps(node.bounds[2 * a + 1], upper[a]);
    }
    for (int c = n; c < 4; ++c) {
      node.child[c] = kInvalidId;
      node.count[c] = 0;
    }
    int inner[4];
    std::uint32_t innerIndex[4];
    int innerCount = 0;
    std::size_t leafCount = 0;
    for (int c = 0; c < n; ++c) innerCount += children[c].leaf ? 0 : 1;
    // Children are numbered after their parent, which lets a refit run bottom-up by walking
    // the nodes backwards; one atomic step per node.
    std::uint32_t nextIndex = innerCount == 0
                                  ? 0
                                  : nextNode_.fetch_add(static_cast<std::uint32_t>(innerCount),
                                                        std::memory_order_relaxed);
    innerCount = 0;
    bool large = false;
    for (int c = 0; c < n; ++c) {
      const Child& child = children[c];
      if (child.leaf) {
        node.child[c] = static_cast<std::uint32_t>(child.range.begin);
        node.count[c] = static_cast<std::uint32_t>(child.range.count());
        ++leafCount;
      } else {
        const std::uint32_t childIndex = nextIndex++;
        node.child[c] = childIndex;
        node.count[c] = 0;
        inner[innerCount] = c;
        innerIndex[innerCount++] = childIndex;
        large = large || child.range.count() > options_.parallelThreshold;
      }
    }
    Counts counts;
    counts.leaves = leafCount;
    counts.maxDepth = static_cast<std::size_t>(depth);
    if (large && innerCount > 1) {
      Counts below[4];
      tbb::parallel_for(0, innerCount, [&](int k) {
        below[k] = buildNode(innerIndex[k], children[inner[k]], depth + 1);
      });
      for (int k = 0; k < innerCount; ++k) counts.merge(below[k]);
    } else {
      for (int k = 0; k < innerCount; ++k)
        counts.merge(buildNode(innerIndex[k], children[inner[k]], depth + 1));
    }
    return counts;
  }

  BvhPrimArray& prims_;
  BvhPrimArray& scratch_;
  const TopLevelBuildOptions& options_;
  const int bins_;
  BvhBuildResult& out_;
  std::atomic<std::uint32_t> nextNode_{0};
};

}  // namespace

void TopLevelBvhBuilder::build(BvhPrimArray& prims, const TopLevelBuildOptions& options,
                               BvhBuildResult& out) {
  Builder(prims, scratch_, options, out).build();
}

}  // namespace tg::detail
