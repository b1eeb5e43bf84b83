// Binned-SAH BVH4 construction (after Wald 2007, "On fast construction of SAH-based bounding
// volume hierarchies"), building four-wide nodes directly: a node starts as one range and
// repeatedly splits its widest splittable child range until it has four, so no binary tree is
// built and collapsed afterwards.
//
// Every range is binned exactly once: the split (or the decision to make it a leaf) travels with
// the range into the node that applies it. Large ranges bin in parallel and build their subtrees
// as parallel tasks; the partition itself stays serial, which costs one pass over the primitives
// per level of the few top levels.
#include "BvhBuilder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>

namespace tg::detail {
namespace {

/// BVH4 levels below which splits are object medians whatever the SAH says: a median split
/// halves a range, which bounds the depth (kBvh4MaxDepth) however skewed the input is.
constexpr int kMedianDepth = 32;

/// A contiguous range of primitives with its bounds and the bounds of its centroids (stored as
/// lower + upper: twice the centre, which saves a multiplication and orders the same).
struct Range {
  std::size_t begin = 0, end = 0;
  Box3f bounds;
  Box3f centroids;
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
};

inline float centroid(const BvhPrim& p, int axis) {
  return p.lower[axis] + p.upper[axis];
}

/// Bin of a centroid coordinate. Clamping in float first keeps the conversion defined for any
/// input (a NaN or an overflowing product lands in bin 0 or the last bin).
inline int binOf(float c, float origin, float scale, int bins) {
  float f = (c - origin) * scale;
  f = f > 0.0f ? f : 0.0f;
  const auto last = static_cast<float>(bins - 1);
  f = f < last ? f : last;
  return static_cast<int>(f);
}

/// Per-axis bin boxes and counts of one range. Plain arrays of which only the first `used`
/// bins are initialised: most ranges are small and bin into a few bins, and initialising all of
/// them would cost more than binning the range.
struct Bins {
  struct Bin {
    float lower[3], upper[3];
    std::uint32_t count;
  };
  Bin bin[3][BvhBuildOptions::kMaxBins];
  int used;

  explicit Bins(int bins) : used(bins) {
    for (auto& axis : bin)
      for (int b = 0; b < used; ++b) {
        for (int k = 0; k < 3; ++k) {
          axis[b].lower[k] = std::numeric_limits<float>::infinity();
          axis[b].upper[k] = -std::numeric_limits<float>::infinity();
        }
        axis[b].count = 0;
      }
  }
  void add(int axis, int b, const BvhPrim& p) {
    Bin& x = bin[axis][b];
    for (int k = 0; k < 3; ++k) {
      x.lower[k] = std::min(x.lower[k], p.lower[k]);
      x.upper[k] = std::max(x.upper[k], p.upper[k]);
    }
    ++x.count;
  }
  void merge(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < used; ++b) {
        Bin& x = bin[a][b];
        const Bin& y = o.bin[a][b];
        for (int k = 0; k < 3; ++k) {
          x.lower[k] = std::min(x.lower[k], y.lower[k]);
          x.upper[k] = std::max(x.upper[k], y.upper[k]);
        }
        x.count += y.count;
      }
  }
  Box3f box(int axis, int b) const {
    const Bin& x = bin[axis][b];
    return {{x.lower[0], x.lower[1], x.lower[2]}, {x.upper[0], x.upper[1], x.upper[2]}};
  }
};

/// Bounds and centroid bounds of a range, in parallel when it is large. Min and max are exact,
/// so the result does not depend on how the range is cut into tasks.
struct RangeBounds {
  Box3f bounds, centroids;
  void add(const BvhPrim& p) {
    bounds.extend(p.box());
    centroids.extend(Vec3f{centroid(p, 0), centroid(p, 1), centroid(p, 2)});
  }
  void merge(const RangeBounds& o) {
    bounds.extend(o.bounds);
    centroids.extend(o.centroids);
  }
};

class Builder {
 public:
  Builder(std::vector<BvhPrim>& prims, const BvhBuildOptions& options, BvhBuildResult& out)
      : prims_(prims),
        options_(options),
        bins_(std::clamp(options.bins, 2, BvhBuildOptions::kMaxBins)),
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
    Range root = makeRange(0, prims_.size());
    out_.bounds = root.bounds;
    // Every inner node has at least two children, except a root that is a single leaf, so
    // there are at most as many nodes as primitives.
    out_.nodes.resize(prims_.size());
    nextNode_.store(1, std::memory_order_relaxed);
    const Split split = decide(root, 0);
    if (split.kind == Split::Kind::Leaf) {
      Bvh4Node& node = out_.nodes[0];
      node = Bvh4Node::makeEmpty();
      node.setBounds(0, root.bounds);
      node.child[0] = 0;
      node.count[0] = static_cast<std::uint32_t>(root.count());
      leaves_.store(1, std::memory_order_relaxed);
    } else {
      buildNode(0, root, split, 0);
    }
    out_.nodes.resize(nextNode_.load(std::memory_order_relaxed));
    out_.leaves = leaves_.load(std::memory_order_relaxed);
    out_.maxDepth = maxDepth_.load(std::memory_order_relaxed);
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

  void binRange(const Range& r, const std::array<float, 3>& origin,
                const std::array<float, 3>& scale, const std::array<bool, 3>& active,
                Bins& bins) const {
    const auto binBlock = [&](std::size_t begin, std::size_t end, Bins& acc) {
      for (std::size_t i = begin; i < end; ++i) {
        const BvhPrim& p = prims_[i];
        for (int a = 0; a < 3; ++a) {
          if (!active[a]) continue;
          acc.add(a, binOf(centroid(p, a), origin[a], scale[a], acc.used), p);
        }
      }
    };
    if (r.count() > options_.parallelThreshold) {
      bins = tbb::parallel_reduce(
          tbb::blocked_range<std::size_t>(r.begin, r.end, 1024), Bins(bins.used),
          [&](const tbb::blocked_range<std::size_t>& block, Bins acc) {
            binBlock(block.begin(), block.end(), acc);
            return acc;
          },
          [&](Bins a, const Bins& b) {
            a.merge(b);
            return a;
          });
    } else {
      binBlock(r.begin, r.end, bins);
    }
  }

  /// Chooses how `r` (a child at BVH4 level `depth`) is split, or that it is a leaf.
  Split decide(const Range& r, int depth) const {
    const std::size_t n = r.count();
    const bool mayBeLeaf = n <= options_.maxLeafSize;
    Split leaf;
    if (n <= 1) return leaf;
    Split median;
    median.kind = Split::Kind::Median;
    median.axis = maxDimension(r.centroids.extent());
    if (depth >= kMedianDepth) return mayBeLeaf ? leaf : median;

    // More bins than primitives only adds empty bins to sweep.
    const int binCount = std::min(bins_, static_cast<int>(std::max<std::size_t>(n, 4)));
    const Vec3f extent = r.centroids.extent();
    std::array<bool, 3> active{};
    std::array<float, 3> origin{}, scale{};
    for (int a = 0; a < 3; ++a) {
      active[a] = extent[a] > 0.0f && (options_.allAxes || a == median.axis);
      origin[a] = r.centroids.lower[a];
      // Slightly fewer than `bins` bins per extent, so the largest centroid stays in the last
      // bin after rounding.
      scale[a] = active[a] ? static_cast<float>(binCount) * 0.99999f / extent[a] : 0.0f;
    }
    if (!active[0] && !active[1] && !active[2]) {
      // All centroids coincide (e.g. instances at one place): no plane separates them.
      return mayBeLeaf ? leaf : median;
    }
    Bins bins(binCount);
    binRange(r, origin, scale, active, bins);

    // Sweep: cost of a split after bin b is area(left) * |left| + area(right) * |right|.
    double bestCost = std::numeric_limits<double>::infinity();
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (!active[a]) continue;
      double rightCost[BvhBuildOptions::kMaxBins];  // written for bins [1, binCount) below
      Box3f acc;
      std::uint32_t count = 0;
      for (int b = binCount - 1; b > 0; --b) {
        acc.extend(bins.box(a, b));
        count += bins.bin[a][b].count;
        rightCost[b] = count == 0 ? -1.0 : double(acc.area()) * count;
      }
      acc = Box3f{};
      count = 0;
      for (int b = 1; b < binCount; ++b) {
        acc.extend(bins.box(a, b - 1));
        count += bins.bin[a][b - 1].count;
        if (count == 0 || rightCost[b] < 0.0) continue;
        const double cost = double(acc.area()) * count + rightCost[b];
        if (cost < bestCost) {
          bestCost = cost;
          best.kind = Split::Kind::Binned;
          best.axis = a;
          best.bins = binCount;
          best.bin = b;
          best.scale = scale[a];
          best.origin = origin[a];
        }
      }
    }
    if (best.kind != Split::Kind::Binned) return mayBeLeaf ? leaf : median;
    if (mayBeLeaf) {
      const double area = r.bounds.area();
      // A range without area (a point or a segment) gives the SAH nothing to weigh: small
      // ones stay leaves.
      if (!(area > 0.0)) return leaf;
      const double leafCost = double(options_.intersectionCost) * double(n);
      const double splitCost =
          double(options_.traversalCost) + double(options_.intersectionCost) * bestCost / area;
      if (leafCost <= splitCost) return leaf;
    }
    return best;
  }

  /// Applies `split` to `r`, giving its two parts with their bounds. The binned partition
  /// gathers the bounds of both sides as it moves primitives: one pass instead of three.
  void apply(const Range& r, const Split& split, Range& left, Range& right) {
    BvhPrim* p = prims_.data();
    std::size_t mid = 0;
    if (split.kind == Split::Kind::Binned) {
      const auto goesLeft = [&](const BvhPrim& prim) {
        return binOf(centroid(prim, split.axis), split.origin, split.scale, split.bins) < split.bin;
      };
      RangeBounds lb, rb;
      std::size_t i = r.begin, j = r.end;
      for (;;) {
        while (i < j && goesLeft(p[i])) lb.add(p[i++]);
        while (i < j && !goesLeft(p[j - 1])) rb.add(p[--j]);
        if (i >= j) break;
        std::swap(p[i], p[j - 1]);
        lb.add(p[i++]);
        rb.add(p[--j]);
      }
      mid = i;
      left = {r.begin, mid, lb.bounds, lb.centroids};
      right = {mid, r.end, rb.bounds, rb.centroids};
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

  void buildNode(std::uint32_t index, const Range& r, const Split& split, int depth) {
    std::size_t seen = maxDepth_.load(std::memory_order_relaxed);
    while (seen < static_cast<std::size_t>(depth) &&
           !maxDepth_.compare_exchange_weak(seen, static_cast<std::size_t>(depth))) {
    }
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
      const Child parent = children[widest];
      Range left, right;
      apply(parent.range, parent.split, left, right);
      children[widest] = {left, decide(left, depth + 1)};
      children[n++] = {right, decide(right, depth + 1)};
    }

    Bvh4Node node = Bvh4Node::makeEmpty();
    Child inner[4];
    std::uint32_t innerIndex[4];
    int innerCount = 0;
    bool large = false;
    for (int c = 0; c < n; ++c) {
      const Child& child = children[c];
      node.setBounds(c, child.range.bounds);
      if (child.split.kind == Split::Kind::Leaf) {
        node.child[c] = static_cast<std::uint32_t>(child.range.begin);
        node.count[c] = static_cast<std::uint32_t>(child.range.count());
        leaves_.fetch_add(1, std::memory_order_relaxed);
      } else {
        // Children are numbered after their parent, which lets a refit run bottom-up by
        // walking the nodes backwards.
        const std::uint32_t childIndex = nextNode_.fetch_add(1, std::memory_order_relaxed);
        node.child[c] = childIndex;
        node.count[c] = 0;
        inner[innerCount] = child;
        innerIndex[innerCount++] = childIndex;
        large = large || child.range.count() > options_.parallelThreshold;
      }
    }
    out_.nodes[index] = node;
    const auto recurse = [&](int k) {
      buildNode(innerIndex[k], inner[k].range, inner[k].split, depth + 1);
    };
    if (large && innerCount > 1) {
      tbb::parallel_for(0, innerCount, recurse);
    } else {
      for (int k = 0; k < innerCount; ++k) recurse(k);
    }
  }

  std::vector<BvhPrim>& prims_;
  const BvhBuildOptions& options_;
  const int bins_;
  BvhBuildResult& out_;
  std::atomic<std::uint32_t> nextNode_{0};
  std::atomic<std::size_t> leaves_{0};
  std::atomic<std::size_t> maxDepth_{0};
};

}  // namespace

void buildBvh4(std::vector<BvhPrim>& prims, const BvhBuildOptions& options, BvhBuildResult& out) {
  Builder(prims, options, out).build();
}

double bvh4SahCost(const Bvh4NodeArray& nodes, double traversalCost, double intersectionCost) {
  if (nodes.empty()) return 0.0;
  const double rootArea = nodes[0].unionBounds().area();
  const bool flat = !(rootArea > 0.0);
  const auto weight = [&](const Box3f& b) { return flat ? 1.0 : double(b.area()); };
  // Depth first from the root, so that the sum is taken in the same order for the same tree
  // whatever numbering a parallel build gave its nodes.
  double sum = traversalCost * (flat ? 1.0 : rootArea);
  std::uint32_t stack[3 * kBvh4MaxDepth + 4];
  int size = 0;
  stack[size++] = 0;
  while (size > 0) {
    const Bvh4Node& node = nodes[stack[--size]];
    for (int s = 0; s < 4; ++s) {
      if (node.child[s] == kInvalidId) continue;
      const double w = weight(node.slotBounds(s));
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
