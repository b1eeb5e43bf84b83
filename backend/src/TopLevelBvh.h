// The top-level 4-wide BVH over instance world boxes (TopLevelKind::Bvh). Internal header:
// callers create it through createTopLevelAccel.
#pragma once

#include <utility>
#include <vector>

#include "Bvh8Twin.h"
#include "BvhAccel.h"
#include "BvhBuilder.h"
#include "TopLevelBvhBuilder.h"
#include "tracegraph/backend/TopLevelAccel.h"

namespace tg::detail {

/// A binned-SAH BVH4 over the instances' world boxes, rebuilt from scratch on every build.
///
/// Same answers as TopLevelKdTree: every instance whose box the ray reaches before the closest
/// hit is intersected through intersectInstance, which applies the tie rule (hitPrecedes). Each
/// instance, or each subtree of one (below), sits in exactly one leaf, so no instance mailbox
/// is needed.
///
/// In scenes of up to a thousand instances, identity instances of BVH objects (the static
/// geometry) are entered by subtree: their widest subtrees stand in the top level for the
/// whole object, up to twice as many entries as instances, so that a ray skips the parts of
/// static chunks it does not reach without entering each chunk's root, and overlapping chunks
/// are walked in one front-to-back order. The subtrees are disjoint and together hold the
/// object's triangles, so each triangle is still tested through exactly one leaf entry.
///
/// The builder bins in parallel for large scenes and keeps its buffers between builds, so a
/// per-frame rebuild does not allocate once the scene has stopped growing.
class TopLevelBvh final : public TopLevelAccel {
 public:
  TopLevelKind kind() const override { return TopLevelKind::Bvh; }
  void build(std::span<const InstanceRecord> instances) override;
  bool intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const override;
  bool occluded(const Ray& ray, TraversalContext& ctx) const override;
  void intersectPacket(const Ray* rays, unsigned lanes, Hit* hits,
                       TraversalContext& ctx) const override;
  void intersectPacketPair(const Ray* rays, unsigned lanes, Hit* hits,
                           TraversalContext& ctx) const override;
  unsigned occludedPacket(const Ray* rays, unsigned lanes, TraversalContext& ctx) const override;
  unsigned occludedPacketPair(const Ray* rays, unsigned lanes,
                              TraversalContext& ctx) const override;
  const TopLevelStats& stats() const override { return stats_; }

 private:
  friend struct TopLevelPacketWalk;
  friend struct TopLevelPairWalk;
  friend struct TopLevelPairLoad;

  /// The lanes of `lanes` (of a packet) whose rays are traceable and blocked by the triangle
  /// ctx.occluder names, if it names one of this build.
  unsigned hintedLanes(const Ray* rays, unsigned lanes, TraversalContext& ctx) const;
  /// occludedPacket without the hint: the lanes walk in groups of equal direction signs, what
  /// is left lane by lane.
  unsigned occludedWalked(const Ray* rays, unsigned lanes, TraversalContext& ctx) const;

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
  /// Eight-wide twins of the nodes below bvh_'s root (buildBvh8BelowRoot) for single rays
  /// (any-hit ones in deep top levels only, see TopLevelBvh.cpp); empty when they are not used
  /// (no AVX2, the portable kernels chosen, or a large or shallow top level).
  Bvh8NodeArray twins_;
  /// bvh_'s root with its inner slots pointing into twins_.
  Bvh4Node wideRoot_ = Bvh4Node::makeEmpty();
  /// What a leaf entry enters: a whole instance, or one subtree of the BVH of an identity
  /// instance (static geometry), whose box then stands in the top level for its own.
  struct Ref {
    std::uint32_t instance = 0;        ///< index of the instance record
    std::uint32_t child = kInvalidId;  ///< the subtree (BvhSubtree); kInvalidId: whole instance
    std::uint32_t count = 0;
    /// The node of the instance's eight-wide tree that stands for inner subtree `child`
    /// (BvhAccel::wideEntryOf), which single rays walk; kInvalidId: walk the BVH4.
    std::uint32_t wide = kInvalidId;
    /// The part of the instance's BVH this entry enters: its root for a whole instance.
    BvhSubtree subtree() const {
      return child == kInvalidId ? BvhSubtree{} : BvhSubtree{{}, child, count};
    }
  };
  /// Closest hit of `ray` (which `enter` enters instances with) in what `ref` names; `box` is
  /// the world ray's box-test constants, which subtrees of identity instances walk with.
  bool intersectRef(const Ref& ref, InstanceEntry& enter, const Ray& ray, const Bvh4Ray& box,
                    Hit& hit, TraversalContext& ctx) const;
  /// Any hit of `ray` in what `ref` names; records the occluder (rememberOccluder).
  bool occludedRef(const Ref& ref, InstanceEntry& enter, const Ray& ray, const Bvh4Ray& box,
                   TraversalContext& ctx) const;
  /// Replaces the primitives of identity instances of BvhAccels by subtrees, widest first,
  /// within kOpenedEntriesPerInstance entries per primitive, and fills opened_: the
  /// primitives' ids then index opened_.
  void openIdentityInstances();

  /// The record of the scene's only instance when that is an identity instance of a BvhAccel
  /// (one static mesh, as a model viewer or a flattened scene holds), else kInvalidId. Single
  /// rays then walk its BVH from the root: a top level of one instance above it is a second
  /// walk and a second set of box-test constants per ray for nothing (6% of a flattened BART
  /// kitchen's single-ray trace).
  std::uint32_t soleIdentity_ = kInvalidId;
  /// The sole identity instance's bounds in slot 0 (the other slots empty): rays that miss them
  /// leave before any object-ray set-up.
  Bvh4Node soleBounds_ = Bvh4Node::makeEmpty();
  /// The box of the whole top level (bvh_.bounds) in slot 0, the other slots empty: closest-hit
  /// single rays and packets from outside it test it before any set-up of the walk, as rays
  /// meet soleBounds_.
  Bvh4Node outerBounds_ = Bvh4Node::makeEmpty();
  std::vector<Ref> refs_;     ///< leaf order
  std::vector<Ref> opened_;   ///< build scratch: what the primitives' ids name
  BvhPrimArray prims_;        ///< build scratch
  BvhPrimArray openedPrims_;  ///< build scratch: prims_ with subtrees
  std::vector<std::pair<float, std::uint32_t>> openHeap_;  ///< build scratch
  TopLevelBvhBuilder builder_;
  TopLevelStats stats_;
};

}  // namespace tg::detail
