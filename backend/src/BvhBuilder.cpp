// Binned-SAH BVH4 construction (after Wald 2007, "On fast construction of SAH-based bounding
// volume hierarchies"), building four-wide nodes directly: a node starts as one range and
// repeatedly splits its widest splittable child range until it has four, so no binary tree is
// built and collapsed afterwards.
//
// Every range is binned at most once (pairs need no bins): the split (or the decision to make it
// a leaf) travels with the range into the node that applies it, with the bounds of both sides
// taken from the bins. Large ranges bin in parallel, partition in parallel chunks
// (partitionChunked) and build their subtrees as parallel tasks. Small subtrees number their
// nodes on their own thread and join the tree as one block.
#include "BvhBuilder.h"

#include "Bvh4Refit.h"
#include "BvhBinning.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <limits>
#include <type_traits>
#include <vector>

namespace tg::detail {
namespace {

/// BVH4 levels below which splits are object medians whatever the SAH says: a median split
/// halves a range, which bounds the depth (kBvh4MaxDepth) however skewed the input is.
constexpr int kMedianDepth = 32;

/// Ranges with at least this many primitives bin into two alternating bin sets (see
/// BinSet::addInterleaved); below it, preparing and merging the second set costs more.
constexpr std::size_t kInterleaveMin = 256;

/// Primitives per extra bin beyond four in binCountFor.
constexpr std::size_t kPrimsPerBin = 20;

/// A contiguous range of primitives with its bounds and the bounds of its centroids (stored as
/// lower + upper: twice the centre, which saves a multiplication and orders the same).
struct Range {
  std::size_t begin = 0, end = 0;
  SseBox bounds;
  SseBox centroids;
  std::size_t count() const { return end - begin; }
};

/// How a range is split, decided once when the range is created.
struct Split {
  enum class Kind : std::uint8_t { Leaf, Binned, Median } kind = Kind::Leaf;
  int axis = 0;
  int bins = 0;      ///< Binned: bin count
  int bin = 0;       ///< Binned: primitives in bins [0, bin) go left
  float scale = 0;   ///< Binned: bins per unit of centroid coordinate
  float origin = 0;  ///< Binned: centroid coordinate of bin 0
  /// Binned: bounds of the two sides, the unions of their bins (exact, as the bins are), so the
  /// partition only gathers the centroid bounds.
  SseBox leftBounds, rightBounds;
};

inline float centroid(const BvhPrim& p, int axis) {
  return p.lower[axis] + p.upper[axis];
}

/// Grows the centroid bounds of the side the centroid `c` goes to, without branching on the
/// side: `m` (all ones: left, zero: right) picks the centroid for one side and the empty corner
/// for the other. Sides are random at the top of the tree, so a branch on them mispredicts half
/// of the time.
inline void addCentroid(__m128 c, __m128 m, SseBox& lc, SseBox& rc) {
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  const __m128 negInf = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  const __m128 cl = _mm_and_ps(m, c), cr = _mm_andnot_ps(m, c);
  lc.extend(_mm_or_ps(cl, _mm_andnot_ps(m, inf)), _mm_or_ps(cl, _mm_andnot_ps(m, negInf)));
  rc.extend(_mm_or_ps(cr, _mm_and_ps(m, inf)), _mm_or_ps(cr, _mm_and_ps(m, negInf)));
}

/// Branch-free Lomuto partition of prims[begin, end) by a binned split on axis `Axis`: every
/// primitive is swapped with the first one of the right side, and the boundary advances when it
/// goes left. The side comes from the centroid the bounds need anyway, binned as
/// BinMapping::bins does (so exactly as the binning did) with its lane broadcast as the mask.
/// Returns the first primitive of the right side.
template <int Axis>
std::size_t partitionBinned(BvhPrim* p, std::size_t begin, std::size_t end, float origin,
                            float scale, int bins, int bin, SseBox& lc, SseBox& rc) {
  const BinMapping map{_mm_set1_ps(origin), _mm_set1_ps(scale),
                       _mm_set1_ps(static_cast<float>(bins - 1))};
  const __m128i split = _mm_set1_epi32(bin);
  // The centroid bounds grow in locals: through the references, the compiler must assume that
  // the swaps' stores may change them, and kept them in memory, which chained every primitive
  // to the previous one's store (partitions took twice as long).
  SseBox leftCentroids = lc, rightCentroids = rc;
  std::size_t mid = begin;
  for (std::size_t i = begin; i < end; ++i) {
    const __m128 lo = primLower(p[i]), hi = primUpper(p[i]);
    const __m128i left = _mm_cmplt_epi32(map.bins(lo, hi), split);
    const __m128i m = _mm_shuffle_epi32(left, Axis * 0x55);
    addCentroid(_mm_add_ps(lo, hi), _mm_castsi128_ps(m), leftCentroids, rightCentroids);
    swapPrims(p[i], p[mid]);
    mid += static_cast<std::size_t>(_mm_cvtsi128_si32(m) & 1);
  }
  lc = leftCentroids;
  rc = rightCentroids;
  return mid;
}

/// partitionBinned for one axis.
using PartitionFn = std::size_t (*)(BvhPrim*, std::size_t, std::size_t, float, float, int, int,
                                    SseBox&, SseBox&);
inline PartitionFn partitionFor(int axis) {
  return axis == 0 ? partitionBinned<0> : axis == 1 ? partitionBinned<1> : partitionBinned<2>;
}

/// Runs of misplaced primitives of a chunked partition, in order: the k-th primitive of one
/// list trades places with the k-th of the other.
class MisplacedRuns {
 public:
  /// Appends the run [first, last) (nothing when it is empty).
  void add(std::size_t first, std::size_t last) {
    if (first >= last) return;
    runs_.push_back({first, last, total_});
    total_ += last - first;
  }
  /// Misplaced primitives in all runs.
  std::size_t total() const { return total_; }
  /// Position of the k-th misplaced primitive (k < total) and the run holding it.
  struct Cursor {
    std::size_t run, at;
  };
  Cursor find(std::size_t k) const {
    std::size_t i = 0;
    while (runs_[i].offset + (runs_[i].last - runs_[i].first) <= k) ++i;
    return {i, runs_[i].first + (k - runs_[i].offset)};
  }
  /// Advances `c` to the next misplaced primitive.
  void next(Cursor& c) const {
    if (++c.at == runs_[c.run].last && c.run + 1 < runs_.size()) c.at = runs_[++c.run].first;
  }

 private:
  struct Run {
    std::size_t first, last, offset;  ///< [first, last), and the misplaced ones before it
  };
  std::vector<Run> runs_;
  std::size_t total_ = 0;
};

/// partitionBinned of a large range in parallel: every chunk of `chunk` primitives is
/// partitioned on its own, then the right-side primitives below the final boundary trade places
/// with the left-side ones above it. Chunks and trades follow from the input alone, so the order
/// left behind is the same on any number of threads.
///
/// The kitchen's tree is skewed at the top (the root keeps 100,682 of 110,520 triangles in one
/// child, which keeps 71,736 in one of its own), so the serial partitions of its first levels
/// kept one thread waiting; chunking them took about 7% off the two-thread build. The first
/// chunk a thread takes was measured to run up to three times slower than its next ones (its
/// lines are still in the other core's cache after the parallel binning), which is why an
/// earlier attempt with exactly two halves gained nothing; with many chunks the faster thread
/// takes more of them.
std::size_t partitionChunked(BvhPrim* p, std::size_t begin, std::size_t end, std::size_t chunk,
                             int axis, float origin, float scale, int bins, int bin, SseBox& lc,
                             SseBox& rc) {
  struct Chunk {
    std::size_t begin, mid, end;
    SseBox lc, rc;
  };
  const PartitionFn partition = partitionFor(axis);
  std::vector<Chunk> chunks((end - begin + chunk - 1) / chunk);
  tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t k) {
    Chunk& c = chunks[k];
    c.begin = begin + k * chunk;
    c.end = std::min(c.begin + chunk, end);
    c.mid = partition(p, c.begin, c.end, origin, scale, bins, bin, c.lc, c.rc);
  });
  std::size_t mid = begin;
  for (const Chunk& c : chunks) {
    mid += c.mid - c.begin;
    lc.extend(c.lc);
    rc.extend(c.rc);
  }
  // Right-side runs [c.mid, c.end) below mid and left-side runs [c.begin, c.mid) from mid on:
  // there are as many of one as of the other.
  MisplacedRuns right, left;
  for (const Chunk& c : chunks) {
    right.add(c.mid, std::min(c.end, mid));
    left.add(std::max(c.begin, mid), c.mid);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, right.total(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& block) {
                      MisplacedRuns::Cursor a = right.find(block.begin());
                      MisplacedRuns::Cursor b = left.find(block.begin());
                      for (std::size_t k = block.begin(); k != block.end(); ++k) {
                        swapPrims(p[a.at], p[b.at]);
                        right.next(a);
                        left.next(b);
                      }
                    });
  return mid;
}

/// Bounds and centroid bounds of a range, in parallel when it is large. Min and max are exact,
/// so the result does not depend on how the range is cut into tasks.
struct RangeBounds {
  SseBox bounds, centroids;
  void add(const BvhPrim& p) {
    const __m128 lo = primLower(p), hi = primUpper(p);
    bounds.extend(lo, hi);
    const __m128 c = _mm_add_ps(lo, hi);
    centroids.extend(c, c);
  }
  void merge(const RangeBounds& o) {
    bounds.extend(o.bounds);
    centroids.extend(o.centroids);
  }
};

class Builder {
 public:
  Builder(BvhPrimArray& prims, const BvhBuildOptions& options, BvhBuildResult& out,
          const BvhPrimBounds* known, Bvh4BuildListener* listener)
      : prims_(prims),
        options_(options),
        bins_(std::clamp(options.bins, 2, BvhBuildOptions::kMaxBins)),
        out_(out),
        known_(known),
        listener_(listener) {}

  void build() {
    out_.leaves = 0;
    out_.maxDepth = 0;
    out_.bounds = Box3f{};
    out_.sahCost = -1.0;
    if (prims_.empty()) {
      out_.nodes.clear();
      return;
    }
    Range root = known_ ? knownRange(*known_) : makeRange(0, prims_.size());
    out_.bounds = root.bounds.box();
    // Every inner node has at least two children, except a root that is a single leaf, so
    // there are at most as many nodes as primitives.
    out_.nodes.resize(prims_.size());
    nextNode_.store(1, std::memory_order_relaxed);
    const Split split = decide(root, 0);
    SubtreeTally tally;
    if (split.kind == Split::Kind::Leaf) {
      Bvh4Node& node = out_.nodes[0];
      node = Bvh4Node::makeEmpty();
      node.setBounds(0, root.bounds.box());
      node.child[0] = 0;
      node.count[0] = static_cast<std::uint32_t>(root.count());
      tally.leaves = 1;
      tally.sah.addSlot(root.bounds.box(), double(options_.intersectionCost) * root.count());
      if (listener_ != nullptr) listener_->nodeBuilt(out_.nodes, 0);
    } else {
      tally = buildNode(TreeNodes{*this}, 0, root, split, 0);
    }
    out_.nodes.resize(nextNode_.load(std::memory_order_relaxed));
    out_.leaves = tally.leaves;
    out_.maxDepth = tally.maxDepth;
    out_.sahCost = tally.sah.finish(out_.bounds, options_.traversalCost);
  }

 private:
  Range makeRange(std::size_t begin, std::size_t end) const {
    RangeBounds rb;
    if (end - begin > options_.parallelThreshold) {
      rb = tbb::parallel_reduce(
          tbb::blocked_range<std::size_t>(begin, end, 1024), RangeBounds{},
          [&](const tbb::blocked_range<std::size_t>& r, RangeBounds acc) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) acc.add(prims_[i]);
            return acc;
          },
          [](RangeBounds a, const RangeBounds& b) {
            a.merge(b);
            return a;
          });
    } else {
      for (std::size_t i = begin; i < end; ++i) rb.add(prims_[i]);
    }
    return {begin, end, rb.bounds, rb.centroids};
  }

  /// The root range from the caller's bounds: what makeRange would gather (lane 3 zero, as
  /// the primitives' loads leave it), without the pass over the primitives.
  Range knownRange(const BvhPrimBounds& b) const {
    return {0, prims_.size(), SseBox::of(b.bounds), SseBox::of(b.centroids)};
  }

  /// Bins `r` on all axes (axis < 0) or on one.
  void binRange(const Range& r, const BinMapping& map, const float* origin, const float* scale,
                int axis, BinSet& bins) const {
    const BvhPrim* p = prims_.data();
    const auto binBlock = [&](std::size_t begin, std::size_t end, BinSet& acc) {
      if (axis < 0 && end - begin >= kInterleaveMin) {
        BinSet odd;
        odd.reset(acc.used);
        acc.addInterleaved(p, begin, end, map, odd);
        acc.merge(odd);
      } else if (axis < 0) {
        acc.add(p, begin, end, map);
      } else {
        acc.addOnAxis(p, begin, end, axis, origin[axis], scale[axis]);
      }
    };
    if (r.count() > options_.parallelThreshold) {
      BinSet empty;
      empty.reset(bins.used);
      bins = tbb::parallel_reduce(
          tbb::blocked_range<std::size_t>(r.begin, r.end, 1024), empty,
          [&](const tbb::blocked_range<std::size_t>& block, BinSet acc) {
            binBlock(block.begin(), block.end(), acc);
            return acc;
          },
          [](BinSet a, const BinSet& b) {
            a.merge(b);
            return a;
          });
    } else {
      binBlock(r.begin, r.end, bins);
    }
  }

  /// Bins for a range of `n` primitives. On all axes: few for small ranges, whose sweep and
  /// bin reset would otherwise cost more than binning their primitives, growing to bins_ at a
  /// few hundred. On one axis the sweep is cheap and fewer bins cost tree quality (about 1.5%
  /// SAH on instance boxes), so there only the bins beyond one per primitive are dropped.
  int binCountFor(std::size_t n) const {
    const std::size_t wanted =
        options_.allAxes ? 4 + n / kPrimsPerBin : std::max<std::size_t>(n, 4);
    return static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(bins_), wanted));
  }

  /// Chooses how `r` (a child at BVH4 level `depth`) is split, or that it is a leaf.
  Split decide(const Range& r, int depth) const {
    const std::size_t n = r.count();
    const bool mayBeLeaf = n <= options_.maxLeafSize;
    Split leaf;
    if (n <= 1) return leaf;
    const Box3f centroids = r.centroids.box();
    const Vec3f extent = centroids.extent();
    Split median;
    median.kind = Split::Kind::Median;
    median.axis = maxDimension(extent);
    if (depth >= kMedianDepth) return mayBeLeaf ? leaf : median;

    const int binCount = binCountFor(n);
    unsigned active = 0;
    alignas(16) float origin[4] = {}, scale[4] = {};
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      active |= 1u << a;
      origin[a] = centroids.lower[a];
      // Slightly fewer than `bins` bins per extent, so the largest centroid stays in the last
      // bin after rounding.
      scale[a] = static_cast<float>(binCount) * 0.99999f / extent[a];
    }
    if (active == 0) {
      // All centroids coincide (e.g. instances at one place): no plane separates them.
      return mayBeLeaf ? leaf : median;
    }
    if (!options_.allAxes) active &= 1u << median.axis;
    if (active == 0) return mayBeLeaf ? leaf : median;
    const BinMapping map{_mm_load_ps(origin), _mm_load_ps(scale),
                         _mm_set1_ps(static_cast<float>(binCount - 1))};
    Split best;
    BinSplit found;
    if (n == 2) {
      found = splitPair(r, active, best.leftBounds, best.rightBounds);
    } else {
      BinSet bins;
      bins.reset(binCount);
      binRange(r, map, origin, scale, options_.allAxes ? -1 : median.axis, bins);
      found = sweepBins(bins, active);
      if (found.axis < 0) return mayBeLeaf ? leaf : median;
      for (int b = 0; b < binCount; ++b) {
        SseBox& side = b < found.bin ? best.leftBounds : best.rightBounds;
        side.extend(bins.box[found.axis][b].lower, bins.box[found.axis][b].upper);
      }
    }
    best.kind = Split::Kind::Binned;
    best.axis = found.axis;
    best.bins = binCount;
    best.bin = found.bin;
    best.scale = scale[found.axis];
    best.origin = origin[found.axis];
    if (mayBeLeaf) {
      const double area = r.bounds.area();
      // A range without area (a point or a segment) gives the SAH nothing to weigh: small
      // ones stay leaves.
      if (!(area > 0.0)) return leaf;
      const double leafCost = double(options_.intersectionCost) * double(n);
      const double splitCost = double(options_.traversalCost) +
                               double(options_.intersectionCost) * double(found.cost) / area;
      if (leafCost <= splitCost) return leaf;
    }
    return best;
  }

  /// The binned split of a range of two primitives without binning them (two fifths of all
  /// ranges are pairs). Their centroids differ on every active axis, so they fall into the
  /// first and the last bin there, and every plane between gives the same cost: the sweep would
  /// take bin 1 of the first active axis, with the primitive of the smaller centroid on the
  /// left. The cost is summed as the sweep sums it, so the tree is the one binning gives.
  BinSplit splitPair(const Range& r, unsigned active, SseBox& left, SseBox& right) const {
    const int axis = std::countr_zero(active);
    const BvhPrim* p = prims_.data() + r.begin;
    const bool firstLeft = centroid(p[0], axis) < centroid(p[1], axis);
    const BvhPrim& l = p[firstLeft ? 0 : 1];
    const BvhPrim& h = p[firstLeft ? 1 : 0];
    left.extend(primLower(l), primUpper(l));
    right.extend(primLower(h), primUpper(h));
    BinSplit found;
    found.axis = axis;
    found.bin = 1;
    found.cost = left.nonEmptyArea() * 1.0f + right.nonEmptyArea() * 1.0f;
    return found;
  }

  /// Applies `split` to `r`, giving its two parts with their bounds. A binned split knows the
  /// sides' bounds from its bins; the partition gathers their centroid bounds as it moves
  /// primitives, so no pass over a side follows.
  void apply(const Range& r, const Split& split, Range& left, Range& right) {
    BvhPrim* p = prims_.data();
    std::size_t mid = 0;
    if (split.kind == Split::Kind::Binned) {
      SseBox lc, rc;
      mid = r.count() > options_.partitionChunk
                ? partitionChunked(p, r.begin, r.end, options_.partitionChunk, split.axis,
                                   split.origin, split.scale, split.bins, split.bin, lc, rc)
                : partitionFor(split.axis)(p, r.begin, r.end, split.origin, split.scale, split.bins,
                                           split.bin, lc, rc);
      left = {r.begin, mid, split.leftBounds, lc};
      right = {mid, r.end, split.rightBounds, rc};
      return;
    }
    // Median: ordered by centroid, then id, so that the halves do not depend on the input order
    // of equal centroids.
    mid = r.begin + r.count() / 2;
    const int axis = split.axis;
    std::nth_element(p + r.begin, p + mid, p + r.end, [axis](const BvhPrim& x, const BvhPrim& y) {
      const float cx = centroid(x, axis), cy = centroid(y, axis);
      return cx < cy || (cx == cy && x.id < y.id);
    });
    left = makeRange(r.begin, mid);
    right = makeRange(mid, r.end);
  }

  /// A child range under construction in buildNode.
  struct Child {
    Range range;
    Split split;
  };

  /// What a subtree's build reports to its parent. Parents merge their children's tallies in
  /// slot order, so the totals (the SAH sum in particular) depend on the tree alone, not on
  /// which thread built which subtree.
  struct SubtreeTally {
    std::size_t leaves = 0;
    std::size_t maxDepth = 0;
    Bvh4SahSum sah;
    void merge(const SubtreeTally& o) {
      leaves += o.leaves;
      maxDepth = std::max(maxDepth, o.maxDepth);
      sah.add(o.sah);
    }
  };

  /// Nodes numbered in the tree itself: indices come from one atomic counter shared by all
  /// threads. Used for the few large subtrees near the root.
  struct TreeNodes {
    Builder& builder;
    std::uint32_t allocate(std::uint32_t count) const {
      return builder.nextNode_.fetch_add(count, std::memory_order_relaxed);
    }
    void store(std::uint32_t index, const Bvh4Node& node) const {
      builder.out_.nodes[index] = node;
    }
  };

  /// Nodes of a small subtree numbered on the thread that builds it (its root is 0), moved into
  /// the tree as one block afterwards (moveIntoTree). Most nodes are in such subtrees; numbering
  /// them through the shared counter would make both threads write one cache line per node,
  /// and would interleave the two threads' nodes in memory.
  struct SubtreeNodes {
    std::vector<Bvh4Node>& nodes;
    std::uint32_t allocate(std::uint32_t count) const {
      const auto first = static_cast<std::uint32_t>(nodes.size());
      nodes.resize(first + count);
      return first;
    }
    void store(std::uint32_t index, const Bvh4Node& node) const { nodes[index] = node; }
  };

  /// Builds the subtree over range `r` whose root is tree node `index`: on this thread with
  /// its own numbering when it is small, else as part of the tree.
  SubtreeTally buildChild(std::uint32_t index, const Range& r, const Split& split, int depth) {
    if (r.count() > options_.parallelThreshold) {
      return buildNode(TreeNodes{*this}, index, r, split, depth);
    }
    std::vector<Bvh4Node> local;
    // A BVH4 has about one inner node per six primitives; the vector grows if it needs more.
    local.reserve(r.count() / 4 + 1);
    local.resize(1);
    const SubtreeTally tally = buildNode(SubtreeNodes{local}, 0, r, split, depth);
    moveIntoTree(index, local);
    return tally;
  }

  /// Copies a subtree numbered by SubtreeNodes into the tree: its root to `rootIndex`, the
  /// other nodes to one block taken from the shared counter. The block is taken after the
  /// parent numbered `rootIndex`, and local numbers put children after their parent, so the
  /// tree keeps that order.
  void moveIntoTree(std::uint32_t rootIndex, const std::vector<Bvh4Node>& local) {
    const auto extra = static_cast<std::uint32_t>(local.size() - 1);
    const std::uint32_t base =
        extra == 0 ? 0 : nextNode_.fetch_add(extra, std::memory_order_relaxed);
    const auto treeIndex = [&](std::uint32_t i) { return i == 0 ? rootIndex : base + i - 1; };
    for (std::uint32_t i = 0; i < local.size(); ++i) {
      Bvh4Node node = local[i];
      for (int s = 0; s < 4; ++s)
        if (node.count[s] == 0 && node.child[s] != kInvalidId)
          node.child[s] = treeIndex(node.child[s]);
      out_.nodes[treeIndex(i)] = node;
    }
    // Local numbers put children after their parents, and so do the tree's: backwards, every
    // node comes after its subtree.
    if (listener_ != nullptr)
      for (auto i = static_cast<std::uint32_t>(local.size()); i-- > 0;)
        listener_->nodeBuilt(out_.nodes, treeIndex(i));
  }

  template <class Nodes>
  SubtreeTally buildNode(const Nodes& nodes, std::uint32_t index, const Range& r,
                         const Split& split, int depth) {
    Child children[4];
    children[0] = {r, split};
    int n = 1;
    while (n < 4) {
      // Open the widest child that is not a leaf: it is the one most rays would enter.
      int widest = -1;
      float widestArea = -1.0f;
      for (int c = 0; c < n; ++c) {
        if (children[c].split.kind == Split::Kind::Leaf) continue;
        const float area = children[c].range.bounds.area();
        if (area > widestArea) {
          widestArea = area;
          widest = c;
        }
      }
      if (widest < 0) break;
      // apply reads the parent before its slot is overwritten below.
      const Child& parent = children[widest];
      Range left, right;
      apply(parent.range, parent.split, left, right);
      children[widest] = {left, decide(left, depth + 1)};
      children[n++] = {right, decide(right, depth + 1)};
    }

    Bvh4Node node = Bvh4Node::makeEmpty();
    int innerSlot[4];  // slots of the inner children, which are built from children[] in place
    std::uint32_t innerIndex[4];
    int innerCount = 0;
    for (int c = 0; c < n; ++c) innerCount += children[c].split.kind == Split::Kind::Leaf ? 0 : 1;
    // Children are numbered after their parent, which lets a refit run bottom-up by walking
    // the nodes backwards.
    std::uint32_t nextIndex =
        innerCount == 0 ? 0 : nodes.allocate(static_cast<std::uint32_t>(innerCount));
    innerCount = 0;
    bool large = false;
    SubtreeTally tally;
    tally.maxDepth = static_cast<std::size_t>(depth);
    for (int c = 0; c < n; ++c) {
      const Child& child = children[c];
      const Box3f box = child.range.bounds.box();
      node.setBounds(c, box);
      if (child.split.kind == Split::Kind::Leaf) {
        node.child[c] = static_cast<std::uint32_t>(child.range.begin);
        node.count[c] = static_cast<std::uint32_t>(child.range.count());
        ++tally.leaves;
      } else {
        const std::uint32_t childIndex = nextIndex++;
        node.child[c] = childIndex;
        node.count[c] = 0;
        innerSlot[innerCount] = c;
        innerIndex[innerCount++] = childIndex;
        large = large || child.range.count() > options_.parallelThreshold;
      }
    }
    nodes.store(index, node);
    SubtreeTally inner[4];
    const auto recurse = [&](int k) {
      const Child& child = children[innerSlot[k]];
      // A subtree numbered on its own thread stays so all the way down.
      if constexpr (std::is_same_v<Nodes, SubtreeNodes>) {
        inner[k] = buildNode(nodes, innerIndex[k], child.range, child.split, depth + 1);
      } else {
        inner[k] = buildChild(innerIndex[k], child.range, child.split, depth + 1);
      }
    };
    if (large && innerCount > 1) {
      tbb::parallel_for(0, innerCount, recurse);
    } else {
      for (int k = 0; k < innerCount; ++k) recurse(k);
    }
    // A node of the tree's own numbering is final once its children are (those of a local
    // subtree are told of as moveIntoTree places them).
    if constexpr (std::is_same_v<Nodes, TreeNodes>)
      if (listener_ != nullptr) listener_->nodeBuilt(out_.nodes, index);
    // The SAH sum in slot order, as refitBvh4 takes it.
    for (int c = 0, k = 0; c < n; ++c) {
      const Child& child = children[c];
      const Box3f box = child.range.bounds.box();
      if (child.split.kind == Split::Kind::Leaf) {
        tally.sah.addSlot(box, double(options_.intersectionCost) * child.range.count());
      } else {
        tally.sah.addSlot(box, options_.traversalCost);
        tally.merge(inner[k++]);
      }
    }
    return tally;
  }

  BvhPrimArray& prims_;
  const BvhBuildOptions& options_;
  const int bins_;
  BvhBuildResult& out_;
  const BvhPrimBounds* known_;
  Bvh4BuildListener* const listener_;
  std::atomic<std::uint32_t> nextNode_{0};
};

}  // namespace

void buildBvh4(BvhPrimArray& prims, const BvhBuildOptions& options, BvhBuildResult& out,
               const BvhPrimBounds* known, Bvh4BuildListener* listener) {
  Builder(prims, options, out, known, listener).build();
}

namespace {

/// Surface areas of the four slot boxes of `node`, each as Box3f::area computes it (0 for an
/// empty box), four at a time from the node's slot-major bounds.
void slotAreas(const Bvh4Node& node, float (&area)[4]) {
  const __m128 lx = _mm_load_ps(node.bounds[0]), ux = _mm_load_ps(node.bounds[1]);
  const __m128 ly = _mm_load_ps(node.bounds[2]), uy = _mm_load_ps(node.bounds[3]);
  const __m128 lz = _mm_load_ps(node.bounds[4]), uz = _mm_load_ps(node.bounds[5]);
  const __m128 dx = _mm_sub_ps(ux, lx), dy = _mm_sub_ps(uy, ly), dz = _mm_sub_ps(uz, lz);
  const __m128 sum =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dy), _mm_mul_ps(dy, dz)), _mm_mul_ps(dz, dx));
  const __m128 empty =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(lx, ux), _mm_cmpgt_ps(ly, uy)), _mm_cmpgt_ps(lz, uz));
  _mm_storeu_ps(area, _mm_andnot_ps(empty, _mm_mul_ps(_mm_set1_ps(2.0f), sum)));
}

}  // namespace

double bvh4SahCost(const Bvh4NodeArray& nodes, double traversalCost, double intersectionCost) {
  if (nodes.empty()) return 0.0;
  const double rootArea = nodes[0].unionBounds().area();
  const bool flat = !(rootArea > 0.0);
  // Depth first from the root, so that the sum is taken in the same order for the same tree
  // whatever numbering a parallel build gave its nodes.
  double sum = traversalCost * (flat ? 1.0 : rootArea);
  std::uint32_t stack[3 * kBvh4MaxDepth + 4];
  int size = 0;
  stack[size++] = 0;
  while (size > 0) {
    const Bvh4Node& node = nodes[stack[--size]];
    float area[4];
    slotAreas(node, area);
    for (int s = 0; s < 4; ++s) {
      if (node.child[s] == kInvalidId) continue;
      const double w = flat ? 1.0 : double(area[s]);
      if (node.count[s] == 0) {
        sum += traversalCost * w;
        stack[size++] = node.child[s];
      } else {
        sum += intersectionCost * node.count[s] * w;
      }
    }
  }
  return sum / (flat ? 1.0 : rootArea);
}

}  // namespace tg::detail
