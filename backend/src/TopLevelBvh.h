// The top-level 4-wide BVH over instance world boxes (TopLevelKind::Bvh). Internal header:
// callers create it through createTopLevelAccel.
#pragma once

#include <vector>

#include "BvhBuilder.h"
#include "TopLevelBvhBuilder.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg::detail {

/// A binned-SAH BVH4 over the instances' world boxes, rebuilt from scratch on every build.
///
/// Same answers as TopLevelKdTree: every instance whose box the ray reaches before the closest
/// hit is intersected through intersectInstance, which applies the tie rule (hitPrecedes). Each
/// instance sits in exactly one leaf, so no instance mailbox is needed. The builder bins in
/// parallel for large scenes and keeps its buffers between builds, so a per-frame rebuild does
/// not allocate once the scene has stopped growing.
class TopLevelBvh final : public TopLevelAccel {
 public:
  TopLevelKind kind() const override { return TopLevelKind::Bvh; }
  void build(std::span<const InstanceRecord> instances) override;
  bool intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const override;
  bool occluded(const Ray& ray, TraversalContext& ctx) const override;
  void intersectPacket(const Ray* rays, unsigned lanes, Hit* hits,
                       TraversalContext& ctx) const override;
  unsigned occludedPacket(const Ray* rays, unsigned lanes, TraversalContext& ctx) const override;
  const TopLevelStats& stats() const override { return stats_; }

 private:
  friend struct TopLevelPacketWalk;

  /// True when ray (traceable) is blocked by the triangle ctx.occluder names, if it names one
  /// of this build (see TraversalContext::OccluderHint).
  bool occludedByHint(const Ray& ray, TraversalContext& ctx) const;
  /// Records in ctx.occluder that instance record `instance` blocked a ray, by the triangle its
  /// accelerator left in ctx.occludingPrimitive.
  void rememberOccluder(std::uint32_t instance, TraversalContext& ctx) const;

  std::span<const InstanceRecord> instances_;
  /// Unique over all top-level builds of the process, so that an occluder hint of another
  /// build (or scene) is never taken for one of this.
  std::uint64_t buildId_ = 0;
  BvhBuildResult bvh_;
  std::vector<std::uint32_t> refs_;  ///< instance indices in leaf order
  std::vector<BvhPrim> prims_;       ///< build scratch
  TopLevelBvhBuilder builder_;
  TopLevelStats stats_;
};

}  // namespace tg::detail
