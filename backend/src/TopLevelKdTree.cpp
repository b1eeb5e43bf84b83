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

/// Recursive Algorithm 1 over index lists; emits nodes depth first, below child first.
class Algorithm1Builder {
 public:
  Algorithm1Builder(std::span<const InstanceRecord> instances, std::vector<KdNode>& nodes,
                    std::vector<std::uint32_t>& refs, TopLevelStats& stats, int maxDepth)
      : instances_(instances), nodes_(nodes), refs_(refs), stats_(stats), maxDepth_(maxDepth) {}

  void build(std::vector<std::uint32_t>& items, const Box3f& cell, int depth) {
    stats_.maxDepth = std::max<std::size_t>(stats_.maxDepth, static_cast<std::size_t>(depth));
    float split = 0.0f;
    int axis = -1;
    if (items.size() > 1 && depth < maxDepth_) axis = choosePlane(items, cell, split);
    if (axis < 0) {
      makeLeaf(items);
      return;
    }
    std::vector<std::uint32_t> below, above;
    below.reserve(items.size());
    above.reserve(items.size());
    for (std::uint32_t i : items) {
      const Box3f& b = instances_[i].worldBounds;
      // A box touching the plane from one side belongs to that side only; a box lying in the
      // plane (zero thickness) belongs to both, since rays in the plane visit both children.
      if (b.lower[axis] < split || b.upper[axis] <= split) below.push_back(i);
      if (b.upper[axis] > split || b.lower[axis] >= split) above.push_back(i);
    }
    if (below.size() == items.size() && above.size() == items.size()) {
      makeLeaf(items);  // every box straddles: splitting would only duplicate references
      return;
    }
    items.clear();
    items.shrink_to_fit();
    Box3f belowCell = cell, aboveCell = cell;
    belowCell.upper[axis] = split;
    aboveCell.lower[axis] = split;
    const std::size_t self = nodes_.size();
    nodes_.emplace_back();
    ++stats_.nodes;
    build(below, belowCell, depth + 1);
    const auto aboveIndex = static_cast<std::uint32_t>(nodes_.size());
    build(above, aboveCell, depth + 1);
    nodes_[self] = KdNode::makeInner(axis, split, aboveIndex);
  }

 private:
  /// Algorithm 1's plane choice. Returns the axis or -1 when no border lies inside the cell.
  int choosePlane(std::vector<std::uint32_t>& items, const Box3f& cell, float& split) {
    const Vec3f extent = cell.extent();
    int axes[3] = {maxDimension(extent), 0, 0};
    axes[1] = (axes[0] + 1) % 3;
    axes[2] = (axes[0] + 2) % 3;
    if (extent[axes[2]] > extent[axes[1]]) std::swap(axes[1], axes[2]);
    for (int axis : axes) {
      const float lo = cell.lower[axis], hi = cell.upper[axis];
      if (!(hi > lo)) continue;
      // Object median: the median of the instance-box centres along the axis.
      centres_.resize(items.size());
      for (std::size_t k = 0; k < items.size(); ++k)
        centres_[k] = instances_[items[k]].worldBounds.center()[axis];
      const auto mid = centres_.begin() + static_cast<std::ptrdiff_t>(centres_.size() / 2);
      std::nth_element(centres_.begin(), mid, centres_.end());
      const float target = 0.5f * (0.5f * (lo + hi) + *mid);
      // Candidate planes: instance-box borders strictly inside the cell; the one nearest the
      // target (ties: the lower position, so the result does not depend on item order).
      float best = 0.0f, bestDistance = kInfinity;
      for (std::uint32_t i : items) {
        const Box3f& b = instances_[i].worldBounds;
        for (float border : {b.lower[axis], b.upper[axis]}) {
          if (!(border > lo && border < hi)) continue;
          const float distance = std::abs(border - target);
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

  void makeLeaf(const std::vector<std::uint32_t>& items) {
    nodes_.push_back(KdNode::makeLeaf(static_cast<std::uint32_t>(refs_.size()),
                                      static_cast<std::uint32_t>(items.size())));
    refs_.insert(refs_.end(), items.begin(), items.end());
    ++stats_.nodes;
    ++stats_.leaves;
  }

  std::span<const InstanceRecord> instances_;
  std::vector<KdNode>& nodes_;
  std::vector<std::uint32_t>& refs_;
  TopLevelStats& stats_;
  int maxDepth_;
  std::vector<float> centres_;
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
  std::vector<std::uint32_t> items;
  items.reserve(instances.size());
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].worldBounds.empty()) continue;
    bounds_.extend(instances[i].worldBounds);
    items.push_back(static_cast<std::uint32_t>(i));
  }
  const double n = static_cast<double>(std::max<std::size_t>(items.size(), 1));
  const int maxDepth = std::min(kKdMaxDepth, static_cast<int>(2.0 * std::log2(n)) + 8);
  nodes_.reserve(4 * items.size() + 1);
  refs_.reserve(2 * items.size());
  Algorithm1Builder(instances, nodes_, refs_, stats_, maxDepth).build(items, bounds_, 0);
  stats_.references = refs_.size();
  stats_.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool TopLevelKdTree::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  if (nodes_.empty()) return false;
  ctx.instanceMailbox.clear();
  float tfar = std::min(ray.tfar, hit.t);
  const Vec3f inverse{1.0f / ray.direction.x, 1.0f / ray.direction.y, 1.0f / ray.direction.z};
  return detail::traverseKdTree<false>(
      nodes_, bounds_, ray.origin, ray.direction, inverse, ray.tnear, tfar, ctx.nodeVisits,
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
  return detail::traverseKdTree<true>(
      nodes_, bounds_, ray.origin, ray.direction, inverse, ray.tnear, ray.tfar, ctx.nodeVisits,
      [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = 0; k < count; ++k) {
          const std::uint32_t i = refs_[first + k];
          if (ctx.instanceMailbox.testAndSet(i)) continue;
          if (occludedInstance(instances_[i], ray, ctx)) return true;
        }
        return false;
      });
}

}  // namespace tg
