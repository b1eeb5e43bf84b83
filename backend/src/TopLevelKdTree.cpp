#include "tracegraph/backend/TopLevelKdTree.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "KdTraversal.h"
#include "TopLevelBvh.h"

namespace tg {

std::string_view topLevelKindName(TopLevelKind kind) {
  switch (kind) {
    case TopLevelKind::KdTree:
      return "kd";
    case TopLevelKind::Bvh:
      return "bvh";
  }
  return "unknown";
}

std::unique_ptr<TopLevelAccel> createTopLevelAccel(TopLevelKind kind) {
  switch (kind) {
    case TopLevelKind::KdTree:
      return std::make_unique<TopLevelKdTree>();
    case TopLevelKind::Bvh:
      return std::make_unique<detail::TopLevelBvh>();
  }
  return nullptr;
}

namespace {

using BuildItem = detail::TopLevelBuildItem;

/// Algorithm 1 over lists of instance boxes kept in one scratch buffer used as a stack: a node
/// owns items[begin, end) and writes its children's lists behind `end`, the above list first,
/// then the below list right after it. The below subtree, built first, grows past both lists and
/// the above list survives it; the above subtree then reuses the dead below list. Nodes are
/// emitted depth first, below child first, and both lists keep the parent's order, so leaves
/// list their instances in index order.
///
/// The boxes travel with the lists, so every pass reads memory sequentially however scattered a
/// node's instances are. Apart from the output, nothing is allocated once the tree's scratch
/// buffers have grown to the scene: rebuilding every frame costs no trips to the allocator.
class Algorithm1Builder {
 public:
  Algorithm1Builder(detail::TopLevelBuildScratch& scratch, std::vector<KdNode>& nodes,
                    std::vector<std::uint32_t>& refs, TopLevelStats& stats, int maxDepth)
      : items_(scratch.items),
        centres_(scratch.centres),
        borders_(scratch.borders),
        nodes_(nodes),
        refs_(refs),
        stats_(stats),
        maxDepth_(maxDepth) {}

  /// A node's cell, indexed by axis without branches.
  struct Cell {
    float lower[3], upper[3];
  };

  void build(std::size_t begin, std::size_t end, const Cell& cell, int depth) {
    stats_.maxDepth = std::max<std::size_t>(stats_.maxDepth, static_cast<std::size_t>(depth));
    const std::size_t count = end - begin;
    const auto self = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    ++stats_.nodes;
    float split = 0.0f;
    int axis = -1;
    if (count > 1 && depth < maxDepth_) {
      axis = choosePlane(items_.data() + begin, count, cell, split);
    }
    if (axis < 0) {
      makeLeaf(self, begin, end);
      return;
    }
    // Room for both children's lists behind this node's list, and for gatherSmall reading past
    // the end of a list.
    if (items_.size() < end + 2 * count + kSmall)
      items_.resize(std::max(end + 2 * count + kSmall, 2 * items_.size()));
    BuildItem* s = items_.data();
    std::size_t above = end, below = end + count;
    for (std::size_t k = begin; k < end; ++k) {
      const BuildItem item = s[k];  // a copy: the stores below may not alias it
      const float lower = item.lower[axis], upper = item.upper[axis];
      // A box touching the plane from one side belongs to that side only; a box lying in the
      // plane (zero thickness) belongs to both, since rays in the plane visit both children.
      // Both slots are written and kept only when the box belongs there: which side a box lies
      // on is unpredictable, a branch would mispredict often.
      s[below] = item;
      below += (lower < split) | (upper <= split);
      s[above] = item;
      above += (upper > split) | (lower >= split);
    }
    const std::size_t aboveCount = above - end, belowCount = below - (end + count);
    if (belowCount == count && aboveCount == count) {
      makeLeaf(self, begin, end);  // every box straddles: splitting would only duplicate references
      return;
    }
    // Close the gap between the lists, so the below subtree can use everything behind them.
    std::copy(s + end + count, s + below, s + above);
    Cell belowCell = cell, aboveCell = cell;
    belowCell.upper[axis] = split;
    aboveCell.lower[axis] = split;
    child(above, above + belowCount, belowCell, depth + 1);
    const auto aboveIndex = static_cast<std::uint32_t>(nodes_.size());
    child(end, above, aboveCell, depth + 1);
    nodes_[self] = KdNode::makeInner(axis, split, aboveIndex);
  }

 private:
  /// Builds a child. Half the nodes are leaves with at most one instance (Algorithm 1 peels empty
  /// space off with planes at box borders); those are emitted here, without the call.
  void child(std::size_t begin, std::size_t end, const Cell& cell, int depth) {
    if (end - begin > 1 && depth < maxDepth_) {
      build(begin, end, cell, depth);
      return;
    }
    stats_.maxDepth = std::max<std::size_t>(stats_.maxDepth, static_cast<std::size_t>(depth));
    nodes_.emplace_back();
    ++stats_.nodes;
    makeLeaf(static_cast<std::uint32_t>(nodes_.size() - 1), begin, end);
  }

  /// Algorithm 1's plane choice. Returns the axis or -1 when no border lies inside the cell.
  int choosePlane(const BuildItem* items, std::size_t count, const Cell& cell, float& split) {
    static constexpr int kNext[3] = {1, 2, 0};
    const float extent[3] = {cell.upper[0] - cell.lower[0], cell.upper[1] - cell.lower[1],
                             cell.upper[2] - cell.lower[2]};
    int axes[3] = {maxDimension(Vec3f(extent[0], extent[1], extent[2])), 0, 0};
    axes[1] = kNext[axes[0]];
    axes[2] = kNext[axes[1]];
    if (extent[axes[2]] > extent[axes[1]]) std::swap(axes[1], axes[2]);
    for (const int axis : axes) {
      const float lo = cell.lower[axis], hi = cell.upper[axis];
      if (!(hi > lo)) continue;
      std::size_t borders = 0;
      float median = 0.0f;
      if (count <= 4) {
        median = gatherSmall<4>(items, count, axis, lo, borders);
      } else if (count <= 8) {
        median = gatherSmall<8>(items, count, axis, lo, borders);
      } else if (count <= kSmall) {
        median = gatherSmall<kSmall>(items, count, axis, lo, borders);
      } else {
        median = gatherLarge(items, count, axis, lo, borders);
      }
      const float target = 0.5f * (0.5f * (lo + hi) + median);
      if (nearestBorder(borders, lo, hi, target, split)) return axis;
    }
    return -1;
  }

  /// Nodes with at most this many instances, most of them, take paths of fixed length without
  /// data-dependent branches: lists this short make every loop exit a misprediction.
  static constexpr std::size_t kSmall = 16;

  /// Copies the borders along `axis` of a node with at most N boxes into borders_ (lower and
  /// upper of box k at 2k and 2k + 1, 2N of them, `lo` for missing boxes: never a candidate) and
  /// returns the object median: the median (the upper one for an even count) of the box
  /// centres. Reads N items whatever the count (the buffer has room behind every list) and masks
  /// the extra ones out.
  template <std::size_t N>
  float gatherSmall(const BuildItem* items, std::size_t count, int axis, float lo,
                    std::size_t& borders) {
    // Selects by masks: a conditional here would compile to a branch taken unpredictably.
    const auto select = [](std::uint32_t mask, float a, float b) {
      return std::bit_cast<float>((std::bit_cast<std::uint32_t>(a) & mask) |
                                  (std::bit_cast<std::uint32_t>(b) & ~mask));
    };
    float* out = borders_.data();
    float c[N];  // centres; missing boxes at infinity sort last
    for (std::size_t k = 0; k < N; ++k) {
      const std::uint32_t valid = 0u - static_cast<std::uint32_t>(k < count);
      const float lower = items[k].lower[axis], upper = items[k].upper[axis];
      out[2 * k] = select(valid, lower, lo);
      out[2 * k + 1] = select(valid, upper, lo);
      c[k] = select(valid, (lower + upper) * 0.5f, kInfinity);
    }
    borders = 2 * N;
    // Batcher's odd-even merge sort (minimum and maximum per comparator). Its first 5 and 19
    // comparators sort the first 4 and 8 entries.
    static constexpr int kNetwork[63][2] = {
        {0, 1},   {2, 3},   {0, 2},   {1, 3},   {1, 2},   {4, 5},  {6, 7},   {4, 6},   {5, 7},
        {5, 6},   {0, 4},   {2, 6},   {2, 4},   {1, 5},   {3, 7},  {3, 5},   {1, 2},   {3, 4},
        {5, 6},   {8, 9},   {10, 11}, {8, 10},  {9, 11},  {9, 10}, {12, 13}, {14, 15}, {12, 14},
        {13, 15}, {13, 14}, {8, 12},  {10, 14}, {10, 12}, {9, 13}, {11, 15}, {11, 13}, {9, 10},
        {11, 12}, {13, 14}, {0, 8},   {4, 12},  {4, 8},   {2, 10}, {6, 14},  {6, 10},  {2, 4},
        {6, 8},   {10, 12}, {1, 9},   {5, 13},  {5, 9},   {3, 11}, {7, 15},  {7, 11},  {3, 5},
        {7, 9},   {11, 13}, {1, 2},   {3, 4},   {5, 6},   {7, 8},  {9, 10},  {11, 12}, {13, 14}};
    static_assert(N == 4 || N == 8 || N == 16);
    constexpr int comparators = N == 4 ? 5 : (N == 8 ? 19 : 63);
    for (int i = 0; i < comparators; ++i) {
      const float a = c[kNetwork[i][0]], b = c[kNetwork[i][1]];
      c[kNetwork[i][0]] = std::min(a, b);
      c[kNetwork[i][1]] = std::max(a, b);
    }
    return c[count / 2];
  }

  /// gatherSmall for any count: borders padded to a multiple of four, median by selection.
  float gatherLarge(const BuildItem* items, std::size_t count, int axis, float lo,
                    std::size_t& borders) {
    float* out = borders_.data();
    float* centres = centres_.data();
    for (std::size_t k = 0; k < count; ++k) {
      const float lower = items[k].lower[axis], upper = items[k].upper[axis];
      out[2 * k] = lower;
      out[2 * k + 1] = upper;
      centres[k] = (lower + upper) * 0.5f;
    }
    borders = (2 * count + 3) & ~std::size_t{3};
    for (std::size_t k = 2 * count; k < borders; ++k) out[k] = lo;
    std::nth_element(centres, centres + count / 2, centres + count);
    return centres[count / 2];
  }

  /// Candidate planes: the gathered borders strictly inside (lo, hi). Finds the one nearest
  /// `target`, the lowest of those at the same (rounded) distance, so that the result does not
  /// depend on the order of the boxes. Returns false when there is no candidate.
  ///
  /// Two passes, the smallest distance and then the lowest border at that distance, each a
  /// plain minimum without branches: which border wins is unpredictable, and most of a build is
  /// spent here and in the partition.
  bool nearestBorder(std::size_t n, float lo, float hi, float target, float& split) const {
    const float* borders = borders_.data();
#if defined(__SSE2__)
    const __m128 vlo = _mm_set1_ps(lo), vhi = _mm_set1_ps(hi), vtarget = _mm_set1_ps(target);
    const __m128 vinf = _mm_set1_ps(kInfinity);
    const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    const auto distances = [&](__m128 b) {
      const __m128 inside = _mm_and_ps(_mm_cmpgt_ps(b, vlo), _mm_cmplt_ps(b, vhi));
      const __m128 d = _mm_and_ps(_mm_sub_ps(b, vtarget), absMask);
      return _mm_or_ps(_mm_and_ps(inside, d), _mm_andnot_ps(inside, vinf));
    };
    const auto horizontalMin = [](__m128 v) {
      v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
      v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
      return _mm_cvtss_f32(v);
    };
    __m128 vmin = vinf;
    for (std::size_t i = 0; i < n; i += 4)
      vmin = _mm_min_ps(vmin, distances(_mm_loadu_ps(borders + i)));
    const float minDistance = horizontalMin(vmin);
    if (!(minDistance < kInfinity)) return false;
    const __m128 vminDistance = _mm_set1_ps(minDistance);
    __m128 vbest = vinf;
    for (std::size_t i = 0; i < n; i += 4) {
      const __m128 b = _mm_loadu_ps(borders + i);
      const __m128 nearest = _mm_cmpeq_ps(distances(b), vminDistance);
      vbest = _mm_min_ps(vbest, _mm_or_ps(_mm_and_ps(nearest, b), _mm_andnot_ps(nearest, vinf)));
    }
    split = horizontalMin(vbest);
#else
    const auto distance = [&](float b) {
      return b > lo && b < hi ? std::abs(b - target) : kInfinity;
    };
    float minDistance = kInfinity;
    for (std::size_t i = 0; i < n; ++i) minDistance = std::min(minDistance, distance(borders[i]));
    if (!(minDistance < kInfinity)) return false;
    float best = kInfinity;
    for (std::size_t i = 0; i < n; ++i)
      if (distance(borders[i]) == minDistance) best = std::min(best, borders[i]);
    split = best;
#endif
    return true;
  }

  void makeLeaf(std::uint32_t self, std::size_t begin, std::size_t end) {
    nodes_[self] = KdNode::makeLeaf(static_cast<std::uint32_t>(refs_.size()),
                                    static_cast<std::uint32_t>(end - begin));
    for (std::size_t k = begin; k < end; ++k) refs_.push_back(items_[k].instance);
    ++stats_.leaves;
  }

  std::vector<BuildItem>& items_;
  std::vector<float>& centres_;
  std::vector<float>& borders_;
  std::vector<KdNode>& nodes_;
  std::vector<std::uint32_t>& refs_;
  TopLevelStats& stats_;
  int maxDepth_;
};

}  // namespace

void TopLevelKdTree::build(std::span<const InstanceRecord> instances) {
  const auto start = std::chrono::steady_clock::now();
  instances_ = instances;
  nodes_.clear();
  refs_.clear();
  stats_ = {};
  stats_.instances = instances.size();
  bounds_ = Box3f{};
  detail::TopLevelBuildScratch& scratch = scratch_;
  // Room for the root list, its children's lists and kSmall slots behind them; deeper levels
  // grow the buffer when they need to.
  if (scratch.items.size() < 3 * instances.size() + 16)
    scratch.items.resize(3 * instances.size() + 16);
  if (scratch.centres.size() < instances.size()) scratch.centres.resize(instances.size());
  if (scratch.borders.size() < 2 * instances.size() + 16)
    scratch.borders.resize(2 * instances.size() + 16);
  std::size_t count = 0;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const Box3f& b = instances[i].worldBounds;
    if (b.empty()) continue;
    bounds_.extend(b);
    scratch.items[count++] = {{b.lower.x, b.lower.y, b.lower.z},
                              {b.upper.x, b.upper.y, b.upper.z},
                              static_cast<std::uint32_t>(i),
                              0};
  }
  const double n = static_cast<double>(std::max<std::size_t>(count, 1));
  const int maxDepth = std::min(kKdMaxDepth, static_cast<int>(2.0 * std::log2(n)) + 8);
  nodes_.reserve(4 * count + 1);
  refs_.reserve(2 * count);
  Algorithm1Builder(scratch, nodes_, refs_, stats_, maxDepth)
      .build(0, count,
             {{bounds_.lower.x, bounds_.lower.y, bounds_.lower.z},
              {bounds_.upper.x, bounds_.upper.y, bounds_.upper.z}},
             0);
  stats_.references = refs_.size();
  stats_.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool TopLevelKdTree::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  if (nodes_.empty()) return false;
  ctx.instanceMailbox.clear();
  float tfar = std::min(ray.tfar, hit.t);
  const Vec3f inverse = reciprocals(ray.direction);
  InstanceEntry enter(ray);
  return detail::traverseKdTree<false>(nodes_, bounds_, ray.origin, ray.direction, inverse,
                                       ray.tnear, tfar, ctx.nodeVisits,
                                       [&](std::uint32_t first, std::uint32_t count) {
                                         bool found = false;
                                         for (std::uint32_t k = 0; k < count; ++k) {
                                           const std::uint32_t i = refs_[first + k];
                                           if (ctx.instanceMailbox.testAndSet(i)) continue;
                                           if (enter.intersect(instances_[i], hit, ctx)) {
                                             tfar = std::min(tfar, hit.t);
                                             found = true;
                                           }
                                         }
                                         return found;
                                       });
}

bool TopLevelKdTree::occluded(const Ray& ray, TraversalContext& ctx) const {
  if (nodes_.empty()) return false;
  ctx.instanceMailbox.clear();
  const Vec3f inverse = reciprocals(ray.direction);
  InstanceEntry enter(ray);
  return detail::traverseKdTree<true>(nodes_, bounds_, ray.origin, ray.direction, inverse,
                                      ray.tnear, ray.tfar, ctx.nodeVisits,
                                      [&](std::uint32_t first, std::uint32_t count) {
                                        for (std::uint32_t k = 0; k < count; ++k) {
                                          const std::uint32_t i = refs_[first + k];
                                          if (ctx.instanceMailbox.testAndSet(i)) continue;
                                          if (enter.occluded(instances_[i], ctx)) return true;
                                        }
                                        return false;
                                      });
}

}  // namespace tg
