// Top-level BVH4: per-frame build over instance world boxes and two-level queries.
#include "TopLevelBvh.h"

#include <algorithm>
#include <chrono>

namespace tg::detail {

void TopLevelBvh::build(std::span<const InstanceRecord> instances) {
  const auto start = std::chrono::steady_clock::now();
  instances_ = instances;
  stats_ = {};
  stats_.instances = instances.size();
  prims_.clear();
  prims_.reserve(instances.size());
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const Box3f& b = instances[i].worldBounds;
    if (!b.empty()) prims_.push_back(BvhPrim::make(b, static_cast<std::uint32_t>(i)));
  }
  BvhBuildOptions options;
  // Entering an instance means a matrix transform and a descent into its object: several node
  // visits' worth. Leaves stay small; only boxes that no plane separates (coincident
  // instances) share a leaf by choice.
  options.bins = 16;
  options.allAxes = false;
  options.maxLeafSize = 2;
  options.traversalCost = 1.0f;
  options.intersectionCost = 4.0f;
  options.parallelThreshold = 8192;
  buildBvh4(prims_, options, bvh_);
  refs_.resize(prims_.size());
  for (std::size_t k = 0; k < prims_.size(); ++k) refs_[k] = prims_[k].id;
  stats_.leaves = bvh_.leaves;
  stats_.nodes = bvh_.nodes.size() + bvh_.leaves;
  stats_.maxDepth = bvh_.maxDepth;
  stats_.references = refs_.size();
  stats_.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

bool TopLevelBvh::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  float tfar = std::min(ray.tfar, hit.t);
  return traverseBvh4<false>(bvh_.nodes, ray.origin, ray.direction, ray.tnear, tfar, ctx.nodeVisits,
                             [&](std::uint32_t first, std::uint32_t count) {
                               bool found = false;
                               for (std::uint32_t k = first; k < first + count; ++k) {
                                 if (intersectInstance(instances_[refs_[k]], ray, hit, ctx)) {
                                   tfar = std::min(tfar, hit.t);
                                   found = true;
                                 }
                               }
                               return found;
                             });
}

bool TopLevelBvh::occluded(const Ray& ray, TraversalContext& ctx) const {
  return traverseBvh4<true>(bvh_.nodes, ray.origin, ray.direction, ray.tnear, ray.tfar,
                            ctx.nodeVisits, [&](std::uint32_t first, std::uint32_t count) {
                              for (std::uint32_t k = first; k < first + count; ++k)
                                if (occludedInstance(instances_[refs_[k]], ray, ctx)) return true;
                              return false;
                            });
}

}  // namespace tg::detail
