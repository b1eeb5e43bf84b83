#include "tracegraph/backend/TopLevelKdTree.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "KdTraversal.h"

namespace tg {

std::string_view topLevelKindName(TopLevelKind kind) {
  switch (kind) {
    case TopLevelKind::KdTree: return "kd";
  }
  return "unknown";
}

std::unique_ptr<TopLevelAccel> createTopLevelAccel(TopLevelKind kind) {
  switch (kind) {
    case TopLevelKind::KdTree: return std::make_unique<TopLevelKdTree>();
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
  Algorithm1Builder(std::vector<BuildItem>& items, std::vector<float>& centres,
                    std::vector<KdNode>& nodes, std::vector<std::uint32_t>& refs,
                    TopLevelStats& stats, int maxDepth)
      : items_(items),
        centres_(centres),
        nodes_(nodes),
        refs_(refs),
        stats_(stats),
        maxDepth_(maxDepth) {}

  void build(std::size_t begin, std::size_t end, const Box3f& cell, int depth) {
    stats_.maxDepth = std::max<std::size_t>(stats_.maxDepth, static_cast<std::size_t>(depth));
    const std::size_t count = end - begin;
    const auto self = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    ++stats_.nodes;
    float split = 0.0f;
    int axis = -1;
    if (count > 1 && depth < maxDepth_)
      axis = choosePlane(items_.data() + begin, count, cell, split);
    if (axis < 0) {
      makeLeaf(self, begin, end);
      return;
    }
    // Room for both children's lists behind this node's list.
    if (items_.size() < end + 2 * count)
      items_.resize(std::max(end + 2 * count, 2 * items_.size()));
    BuildItem* s = items_.data();
    std::size_t above = end, below = end + count;
    for (std::size_t k = begin; k < end; ++k) {
      const BuildItem& item = s[k];
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
    Box3f belowCell = cell, aboveCell = cell;
    belowCell.upper[axis] = split;
    aboveCell.lower[axis] = split;
    build(above, above + belowCount, belowCell, depth + 1);
    const auto aboveIndex = static_cast<std::uint32_t>(nodes_.size());
    build(end, above, aboveCell, depth + 1);
    nodes_[self] = KdNode::makeInner(axis, split, aboveIndex);
  }

 private:
  /// Algorithm 1's plane choice. Returns the axis or -1 when no border lies inside the cell.
  int choosePlane(const BuildItem* items, std::size_t count, const Box3f& cell, float& split) {
    static constexpr int kNext[3] = {1, 2, 0};
    const Vec3f extent = cell.extent();
    int axes[3] = {maxDimension(extent), 0, 0};
    axes[1] = kNext[axes[0]];
    axes[2] = kNext[axes[1]];
    if (extent[axes[2]] > extent[axes[1]]) std::swap(axes[1], axes[2]);
    for (const int axis : axes) {
      const float lo = cell.lower[axis], hi = cell.upper[axis];
      if (!(hi > lo)) continue;
      const float target = 0.5f * (0.5f * (lo + hi) + medianCentre(items, count, axis));
      // Candidate planes: instance-box borders strictly inside the cell; the one nearest the
      // target (ties: the lower position, so the result does not depend on item order).
      float best = 0.0f, bestDistance = kInfinity;
      for (std::size_t k = 0; k < count; ++k) {
        for (const float border : {items[k].lower[axis], items[k].upper[axis]}) {
          const float distance = border > lo && border < hi ? std::abs(border - target) : kInfinity;
          if (distance < bestDistance || (distance == bestDistance && border < best)) {
            best = border;
            bestDistance = distance;
          }
        }
      }
      if (bestDistance < kInfinity) {
        split = best;
        return axis;
      }
    }
    return -1;
  }

  /// The object median: the median (the upper one for an even count) of the box centres.
  float medianCentre(const BuildItem* items, std::size_t count, int axis) {
    float* centres = centres_.data();
    for (std::size_t k = 0; k < count; ++k)
      centres[k] = (items[k].lower[axis] + items[k].upper[axis]) * 0.5f;
    // Most nodes hold a handful of instances; sorting those directly is cheaper than a general
    // selection.
    if (count <= 8) {
      for (std::size_t k = 1; k < count; ++k) {
        const float c = centres[k];
        std::size_t j = k;
        for (; j > 0 && c < centres[j - 1]; --j) centres[j] = centres[j - 1];
        centres[j] = c;
      }
    } else {
      std::nth_element(centres, centres + count / 2, centres + count);
    }
    return centres[count / 2];
  }

  void makeLeaf(std::uint32_t self, std::size_t begin, std::size_t end) {
    nodes_[self] = KdNode::makeLeaf(static_cast<std::uint32_t>(refs_.size()),
                                    static_cast<std::uint32_t>(end - begin));
    for (std::size_t k = begin; k < end; ++k) refs_.push_back(items_[k].instance);
    ++stats_.leaves;
  }

  std::vector<BuildItem>& items_;
  std::vector<float>& centres_;
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
  if (buildItems_.size() < 3 * instances.size()) buildItems_.resize(3 * instances.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const Box3f& b = instances[i].worldBounds;
    if (b.empty()) continue;
    bounds_.extend(b);
    buildItems_[count++] = {{b.lower.x, b.lower.y, b.lower.z},
                            {b.upper.x, b.upper.y, b.upper.z},
                            static_cast<std::uint32_t>(i)};
  }
  if (centres_.size() < count) centres_.resize(count);
  const double n = static_cast<double>(std::max<std::size_t>(count, 1));
  const int maxDepth = std::min(kKdMaxDepth, static_cast<int>(2.0 * std::log2(n)) + 8);
  nodes_.reserve(4 * count + 1);
  refs_.reserve(2 * count);
  Algorithm1Builder(buildItems_, centres_, nodes_, refs_, stats_, maxDepth)
      .build(0, count, bounds_, 0);
  stats_.references = refs_.size();
  stats_.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool TopLevelKdTree::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  if (nodes_.empty()) return false;
  ctx.instanceMailbox.clear();
  float tfar = std::min(ray.tfar, hit.t);
  const Vec3f inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  return detail::traverseKdTree<false>(nodes_, bounds_, ray.origin, ray.direction, inverse,
                                       ray.tnear, tfar, ctx.nodeVisits,
                                       [&](std::uint32_t first, std::uint32_t count) {
                                         bool found = false;
                                         for (std::uint32_t k = 0; k < count; ++k) {
                                           const std::uint32_t i = refs_[first + k];
                                           if (ctx.instanceMailbox.testAndSet(i)) continue;
                                           if (intersectInstance(instances_[i], ray, hit, ctx)) {
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
  const Vec3f inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  return detail::traverseKdTree<true>(nodes_, bounds_, ray.origin, ray.direction, inverse,
                                      ray.tnear, ray.tfar, ctx.nodeVisits,
                                      [&](std::uint32_t first, std::uint32_t count) {
                                        for (std::uint32_t k = 0; k < count; ++k) {
                                          const std::uint32_t i = refs_[first + k];
                                          if (ctx.instanceMailbox.testAndSet(i)) continue;
                                          if (occludedInstance(instances_[i], ray, ctx))
                                            return true;
                                        }
                                        return false;
                                      });
}

}  // namespace tg
