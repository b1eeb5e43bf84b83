// Top-level BVH4: per-frame build over instance world boxes and two-level queries.
#include "TopLevelBvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <new>
#include <utility>

#include "Bvh8Walk.h"
#include "BvhAccel.h"
#include "PacketObjectRays.h"
#include "PacketRays.h"
#include "PacketTransformedRays.h"
#include "tracegraph/backend/Simd.h"

namespace tg::detail {
namespace {

/// Instance counts from which the copies into and out of the builder run in parallel.
constexpr std::size_t kParallelCopy = 16384;

/// Source of TopLevelBvh::buildId_ (0 is no build).
std::atomic<std::uint64_t> lastBuildId{0};

/// Scenes of at most this many instances enter their identity instances by subtree
/// (TopLevelBvh::openIdentityInstances); larger ones, whose per-frame build time matters more,
/// enter whole instances.
constexpr std::size_t kOpenMaxInstances = 1024;

/// Leaf entries the top level may hold per instance once identity instances are opened.
constexpr double kOpenedEntriesPerInstance = 2.0;

/// Top levels of at most this many entries get eight-wide twins for single rays (Bvh8Walk.h);
/// they cost one pass over the nodes per build. Larger ones, whose per-frame build time
/// matters more, are walked four-wide.
constexpr std::size_t kTwinMaxEntries = 4096;
/// Nor do shallow ones (nodes at most two levels below the root): there the twins open little,
/// and the BART museum's (32 entries in 13 nodes) traced 3-4% slower from its camera.
constexpr std::size_t kTwinMinDepth = 3;
/// Any-hit single rays walk the twins only in deeper top levels. A blocked ray's walk goes
/// straight down to its blocker, so the twins save it about half the levels, at a price per
/// ray. Unhinted shadow rays from the BART cameras, one thread, time as a share of Embree
/// MEDIUM's rtcOccluded1, first with the top levels walked farthest middle first: the robots
/// (depth 6) 1.17-1.19 -> 1.04-1.07 through the twins (3.9 -> 2.7 node visits per ray; from
/// outside 0.88-0.90 -> 0.94-0.96), the kitchen (depth 4) 1.12-1.16 -> 1.20-1.21. Then, two
/// threads, in the any-hit order of Bvh4.h (highest slot first): the robots' walk through the
/// twins 2.67 -> 2.00 visits per ray, while through twins the kitchen's would rise from 2.01
/// to 3.84 and its time from 1.16 to 1.99 of Embree's (an opened slot's children do not all keep
/// its place among a twin's slots, so the upper side of a split is not always taken first).
constexpr std::size_t kAnyHitTwinMinDepth = 5;

/// Success rate (TraversalContext::OccluderHint::successRate, in 1/65536) below which the
/// occluder hint is not tested on every query. A failed test costs about a seventh of an
/// occluded ray's walk (the built-in sphereflake's shadow rays, whose hint succeeds 9.5% of the
/// time: 10.6 ms hinted, 10.1 ms without the hint), so the hint pays from about one success in
/// seven; a fifth leaves a margin. The BART kitchen's and robots' shadow rays succeed 55-100%
/// of the time.
constexpr std::uint16_t kHintWorthRate = 65536 / 5;
/// While the rate is below kHintWorthRate, the hint is tested on one query in this many.
constexpr std::uint16_t kHintProbeInterval = 8;

/// A node holding `box` in slot 0 and nothing in the others: the box, for the node test's
/// widened arithmetic (see meetsOneBox).
Bvh4Node oneBoxNode(const Box3f& box) {
  Bvh4Node node = Bvh4Node::makeEmpty();
  node.setBounds(0, box);
  return node;
}

/// True when `ray` meets the box of a oneBoxNode within [tnear, tfar]: a box test before a
/// walk's set-up, which keeps every ray the walk below it could keep.
bool meetsOneBox(const Bvh4Node& node, const Bvh4Ray& ray, float tfar) {
  float entry[4];
  return (intersectBvh4Node(node, ray, tfar, entry) & 1u) != 0;
}

/// True when `accel` is a BvhAccel, whose packet walk takes rays loaded once per top-level walk.
bool isBvhAccel(const ObjectAccel& accel) {
  return accel.kind() == AccelKind::Bvh || accel.kind() == AccelKind::BvhFast;
}

}  // namespace

void TopLevelBvh::build(std::span<const InstanceRecord> instances) {
  const auto start = std::chrono::steady_clock::now();
  instances_ = instances;
  buildId_ = lastBuildId.fetch_add(1, std::memory_order_relaxed) + 1;
  stats_ = {};
  stats_.instances = instances.size();
  // Large scenes make the primitives in parallel, at their instance's index; empty boxes (none
  // from Scene::commit, which leaves out empty objects) are taken out afterwards.
  const std::size_t n = instances.size();
  prims_.resize(n);
  const auto fill = [&](std::size_t begin, std::size_t end) {
    std::size_t empty = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const Box3f& b = instances[i].worldBounds;
      prims_[i] = BvhPrim::make(b, static_cast<std::uint32_t>(i));
      empty += b.empty() ? 1 : 0;
    }
    return empty;
  };
  std::size_t empty = 0;
  if (n >= kParallelCopy) {
    std::atomic<std::size_t> total{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        total.fetch_add(fill(r.begin(), r.end()), std::memory_order_relaxed);
                      });
    empty = total.load(std::memory_order_relaxed);
  } else {
    empty = fill(0, n);
  }
  if (empty != 0) std::erase_if(prims_, [](const BvhPrim& p) { return p.box().empty(); });
  opened_.clear();
  soleIdentity_ = kInvalidId;
  if (prims_.size() == 1) {
    const InstanceRecord& inst = instances_[prims_[0].id];
    if (inst.identity && isBvhAccel(*inst.accel)) {
      soleIdentity_ = prims_[0].id;
      soleBounds_ = oneBoxNode(inst.accel->bounds());
    }
  }
  if (prims_.size() <= kOpenMaxInstances) openIdentityInstances();
  TopLevelBuildOptions options;
  // Entering an instance means a matrix transform and a descent into its object: several node
  // visits' worth. Leaves stay small; only boxes that no plane separates (coincident
  // instances) share a leaf by choice.
  options.bins = 16;
  options.maxLeafSize = 2;
  options.traversalCost = 1.0f;
  options.intersectionCost = 4.0f;
  options.parallelThreshold = 8192;
  if (!opened_.empty()) {
    // Subtrees of objects of every size in one tree: the fast builder's single binned axis
    // built trees that made rays from outside the BART robots 23% slower than whole
    // instances; binning every axis brought that to 8%, and a few hundred entries build in
    // well under a millisecond.
    BvhBuildOptions full;
    full.bins = 32;
    full.allAxes = true;
    full.maxLeafSize = options.maxLeafSize;
    full.traversalCost = options.traversalCost;
    full.intersectionCost = options.intersectionCost;
    buildBvh4(prims_, full, bvh_);
  } else {
    builder_.build(prims_, options, bvh_);
  }
  refs_.resize(prims_.size());
  const auto copyIds = [&](std::size_t begin, std::size_t end) {
    if (opened_.empty()) {
      for (std::size_t k = begin; k < end; ++k) refs_[k] = Ref{prims_[k].id, kInvalidId, 0};
    } else {
      for (std::size_t k = begin; k < end; ++k) refs_[k] = opened_[prims_[k].id];
    }
  };
  if (refs_.size() >= kParallelCopy) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, refs_.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& r) { copyIds(r.begin(), r.end()); });
  } else {
    copyIds(0, refs_.size());
  }
  outerBounds_ = bvh_.nodes.empty() ? Bvh4Node::makeEmpty() : oneBoxNode(bvh_.bounds);
  // Closest-hit single rays from inside the top level's box walk eight-wide twins where the
  // CPU runs AVX2 (Bvh8Walk.h), made only for the nodes a walk from the root reaches (the robots'
  // 661 instances: top-level rebuilds of 0.132-0.135 ms against 0.142-0.145 with a twin for
  // every node, and the same walk). One thread, alternating processes, time as a share of Embree
  // MEDIUM's rtcIntersect1: robots from its camera (the top level 13.2 of a ray's 17.7 node
  // visits) 1.27-1.28 -> 1.13-1.16, kitchen 1.14 -> 1.13 (within the spread). Rays from
  // outside keep the BVH4: through the twins the kitchen's took 6-9% and the robots' 3-7% more
  // time, and the kitchen's two-level overhead rose from 1.05 to 1.10.
  twins_.clear();
#if TG_BVH8_WALK
  if (refs_.size() <= kTwinMaxEntries && bvh_.maxDepth >= kTwinMinDepth &&
      activeSimdIsa() != SimdIsa::Portable)
    buildBvh8BelowRoot(bvh_.nodes, wideRoot_, twins_);
#endif
  stats_.leaves = bvh_.leaves;
  stats_.nodes = bvh_.nodes.size() + bvh_.leaves;
  stats_.maxDepth = bvh_.maxDepth;
  stats_.references = refs_.size();
  stats_.buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void TopLevelBvh::openIdentityInstances() {
  const auto opens = [&](const BvhPrim& p) {
    const InstanceRecord& inst = instances_[p.id];
    return inst.identity && isBvhAccel(*inst.accel);
  };
  if (std::none_of(prims_.begin(), prims_.end(), opens)) return;
  openedPrims_.clear();
  // Inner subtrees not yet opened, by surface area (a max-heap: the widest opens first).
  std::vector<std::pair<float, std::uint32_t>>& heap = openHeap_;
  heap.clear();
  for (const BvhPrim& p : prims_) {
    const auto index = static_cast<std::uint32_t>(opened_.size());
    openedPrims_.push_back(BvhPrim::make(p.box(), index));
    if (!opens(p)) {
      opened_.push_back(Ref{p.id, kInvalidId, 0});
      continue;
    }
    const auto& bvh = static_cast<const BvhAccel&>(*instances_[p.id].accel);
    opened_.push_back(Ref{p.id, 0, 0, bvh.wideEntryOf(0)});
    heap.emplace_back(p.box().area(), index);
  }
  std::make_heap(heap.begin(), heap.end());
  const auto budget =
      static_cast<std::size_t>(static_cast<double>(prims_.size()) * kOpenedEntriesPerInstance);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end());
    const std::uint32_t index = heap.back().second;
    heap.pop_back();
    const Ref ref = opened_[index];
    const auto& bvh = static_cast<const BvhAccel&>(*instances_[ref.instance].accel);
    BvhSubtree children[4];
    const int n = bvh.subtreeChildren(ref.subtree(), children);
    if (n == 0) continue;
    if (opened_.size() + static_cast<std::size_t>(n) - 1 > budget) break;
    for (int c = 0; c < n; ++c) {
      const std::uint32_t at = c == 0 ? index : static_cast<std::uint32_t>(opened_.size());
      const Ref child{ref.instance, children[c].child, children[c].count,
                      children[c].count == 0 ? bvh.wideEntryOf(children[c].child) : kInvalidId};
      const BvhPrim prim = BvhPrim::make(children[c].bounds, at);
      if (c == 0) {
        opened_[at] = child;
        openedPrims_[at] = prim;
      } else {
        opened_.push_back(child);
        openedPrims_.push_back(prim);
      }
      if (children[c].count == 0) {
        heap.emplace_back(children[c].bounds.area(), at);
        std::push_heap(heap.begin(), heap.end());
      }
    }
  }
  prims_.swap(openedPrims_);
}

bool TopLevelBvh::intersectRef(const Ref& ref, InstanceEntry& enter, const Ray& ray,
                               const Bvh4Ray& box, Hit& hit, TraversalContext& ctx) const {
  const InstanceRecord& inst = instances_[ref.instance];
  if (ref.child == kInvalidId) return enter.intersect(inst, hit, ctx);
  // An identity instance's object ray is the world ray: its box-test constants are `box`'s
  // (Bvh4Ray from the same origin, direction, reciprocals and tnear), not made again per entry.
  ObjectRay& objectRay = enter.identityRay(inst, hit.t < ray.tfar ? hit.t : ray.tfar);
  const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
  if (ref.wide != kInvalidId) return bvh.intersectWideSubtree(objectRay, box, hit, ref.wide, ctx);
  return bvh.intersectSubtree(objectRay, box, hit, ref.child, ref.count, ctx);
}

bool TopLevelBvh::occludedRef(const Ref& ref, InstanceEntry& enter, const Ray& ray,
                              const Bvh4Ray& box, TraversalContext& ctx) const {
  const InstanceRecord& inst = instances_[ref.instance];
  bool blocked = false;
  if (ref.child == kInvalidId) {
    blocked = enter.occluded(inst, ctx);
  } else {
    const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
    const ObjectRay& objectRay = enter.identityRay(inst, ray.tfar);
    blocked = ref.wide != kInvalidId
                  ? bvh.occludedWideSubtree(objectRay, box, ref.wide, ctx)
                  : bvh.occludedSubtree(objectRay, box, ref.child, ref.count, ctx);
  }
  if (blocked) rememberOccluder(ref.instance, ctx);
  return blocked;
}

bool TopLevelBvh::intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const {
  if (soleIdentity_ != kInvalidId) {
    // intersectInstance without the virtual call: the accelerator is a BvhAccel (build()).
    const InstanceRecord& inst = instances_[soleIdentity_];
    const float tfar = hit.t < ray.tfar ? hit.t : ray.tfar;
    const Bvh4Ray box(ray.origin, ray.direction, ray.tnear);
    // Its bounds first: from outside a scene many rays miss them, and then need neither the
    // object ray's shear constants nor a walk (the flattened BART kitchen from outside traced
    // 15% faster, from its camera 2-4% slower). Counted as the visit of the root it stands for.
    if (!meetsOneBox(soleBounds_, box, tfar)) {
      ++ctx.nodeVisits;
      return false;
    }
    ObjectRay objectRay = objectRayFor(inst, ray, tfar);
    return static_cast<const BvhAccel&>(*inst.accel).intersectWhole(objectRay, box, hit, ctx);
  }
  float tfar = std::min(ray.tfar, hit.t);
  const Bvh4Ray box(ray.origin, ray.direction, ray.tnear);
  const bool inside = bvh_.bounds.contains(ray.origin);
  if (!inside) {
    // Rays from outside meet the top level's box before the walk's set-up, as soleBounds_ is
    // met: most of those that miss it (four fifths of the rays from a camera framing the BART
    // kitchen's bounds) then cost one box test. Counted as the visit of the root it stands for.
    // Two-level overhead (`tg-bench overhead`, one thread, alternating processes): kitchen
    // 1.108 and 1.109 -> 1.034 and 1.034, robots 1.069 and 1.057 -> 0.997 and 1.002.
    if (!meetsOneBox(outerBounds_, box, tfar)) {
      ++ctx.nodeVisits;
      return false;
    }
  }
  InstanceEntry enter(ray);
  const auto leaf = [&](std::uint32_t first, std::uint32_t count) {
    bool found = false;
    for (std::uint32_t k = first; k < first + count; ++k) {
      if (intersectRef(refs_[k], enter, ray, box, hit, ctx)) {
        tfar = std::min(tfar, hit.t);
        found = true;
      }
    }
    return found;
  };
#if TG_BVH8_WALK
  // Rays from outside the top level's box (bvh_.bounds) keep the BVH4 walk (see build()).
  if (!twins_.empty() && inside)
    return traverseBvh8<false>(wideRoot_, twins_, box, tfar, ctx.nodeVisits, leaf);
#endif
  return traverseBvh4From<false>(bvh_.nodes, 0, 0, box, tfar, ctx.nodeVisits, leaf);
}

bool TopLevelBvh::occludedByHint(const Ray& ray, TraversalContext& ctx) const {
  TraversalContext::OccluderHint& hint = ctx.occluder;
  if (hint.build != buildId_) return false;
  if (hint.successRate < kHintWorthRate) {
    if (++hint.skipped < kHintProbeInterval) return false;
    hint.skipped = 0;
  }
  const InstanceRecord& inst = instances_[hint.instance];
  ++ctx.triangleTests;
  const bool occluded =
      inst.accel->occludedByPrimitive(objectRayFor(inst, ray, ray.tfar), hint.primitive);
  // A moving average over about sixteen tests: rate += (outcome - rate) / 16.
  const int outcome = occluded ? 65535 : 0;
  hint.successRate =
      static_cast<std::uint16_t>(hint.successRate + (outcome - int(hint.successRate)) / 16);
  return occluded;
}

void TopLevelBvh::rememberOccluder(std::uint32_t instance, TraversalContext& ctx) const {
  // A new triangle, the same stream of queries: the success rate carries over.
  ctx.occluder.build = buildId_;
  ctx.occluder.instance = instance;
  ctx.occluder.primitive = ctx.occludingPrimitive;
}

bool TopLevelBvh::occluded(const Ray& ray, TraversalContext& ctx) const {
  // The hint's triangle first: true only where the walk would find the ray occluded as well.
  if (occludedByHint(ray, ctx)) return true;
  if (soleIdentity_ != kInvalidId) {
    if (!occludedInstance(instances_[soleIdentity_], ray, ctx)) return false;
    rememberOccluder(soleIdentity_, ctx);
    return true;
  }
  InstanceEntry enter(ray);
  // Highest slot first, as every any-hit walk (Bvh4.h). The walk is given its box ray directly:
  // called through traverseBvh4, GCC kept it out of line here, and these rays from outside the
  // kitchen took 10% longer.
  const Bvh4Ray box(ray.origin, ray.direction, ray.tnear);
  const auto leaf = [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t k = first; k < first + count; ++k)
      if (occludedRef(refs_[k], enter, ray, box, ctx)) return true;
    return false;
  };
#if TG_BVH8_WALK
  if (!twins_.empty() && bvh_.maxDepth >= kAnyHitTwinMinDepth && bvh_.bounds.contains(ray.origin))
    return traverseBvh8<true>(wideRoot_, twins_, box, ray.tfar, ctx.nodeVisits, leaf);
#endif
  return traverseBvh4From<true>(bvh_.nodes, 0, 0, box, ray.tfar, ctx.nodeVisits, leaf);
}

namespace {

/// An ObjectRayPacket whose lanes are written before they are read. A constructed packet writes
/// the default values of all its rays (a kilobyte), which a walk over a few instances would pay
/// on every packet; ObjectRayPacket is an aggregate, so byte storage provides one without them.
class UninitialisedObjectPacket {
 public:
  UninitialisedObjectPacket() {}  // leaves the storage as it is, on purpose
  ObjectRayPacket& get() { return *std::launder(reinterpret_cast<ObjectRayPacket*>(storage_)); }

 private:
  alignas(ObjectRayPacket) std::byte storage_[sizeof(ObjectRayPacket)];
};

}  // namespace

/// The packet walk over instances: world rays in the kernel, object packets into each instance
/// a leaf holds (mapped lane by lane exactly as objectRayFor maps single rays).
///
/// Identity instances (all static geometry is one) see the world rays themselves, so their
/// object packet, with its shear constants and reciprocals, and the BVH's loaded form of it are
/// computed once per walk, for all its lanes, at the first identity instance entered; entering
/// one only rewrites tfar and the ids.
struct TopLevelPacketWalk {
  using Ref = TopLevelBvh::Ref;

  TopLevelPacketWalk(const TopLevelBvh* top_, const Ray* rays_, Hit* hits_, TraversalContext* ctx_,
                     const PacketKernels* kernels_)
      : top(top_), rays(rays_), hits(hits_), ctx(ctx_), kernels(kernels_) {}

  const TopLevelBvh* top;
  const Ray* rays;
  Hit* hits;
  TraversalContext* ctx;
  /// The kernels of the walk and of the identity instances it enters.
  const PacketKernels* kernels;
  /// Lanes of the walk (set by load).
  unsigned walkLanes = 0;
  /// Object packet of the transformed instance being entered.
  UninitialisedObjectPacket mapped;
  /// Object packet of identity instances; valid once identityReady, as are the triangle rows
  /// of identityBvh and the lanes they serve.
  UninitialisedObjectPacket identity;
  bool identityReady = false;
  unsigned identityFiltered = 0;
  /// `identity` loaded for BvhAccel; valid once identityBvhReady.
  BvhPacketRays identityBvh;
  bool identityBvhReady = false;
  /// `mapped` loaded for the transformed BvhAccel instance being entered.
  BvhPacketRays transformedBvh;

  /// The identity packet, with the triangle rows of identityBvh and the lanes they serve, made
  /// at the first identity instance `inst` the walk enters. The lanes' object rays are made when
  /// a test needs one (BvhAccel::packetLane), or in objectPacket for an accelerator that reads the
  /// packet's rays themselves; callers set tfar and the ids.
  ObjectRayPacket& identityPacket(const InstanceRecord& inst) {
    if (!identityReady) {
      const LoadedLanes found = kernels->loadIdentityRows(rays, walkLanes, identityBvh.triangles);
      setTrianglePermutation(found, identityBvh.triangles);
      identityFiltered = found.filtered;
      identityBvh.unmappedLanes = walkLanes;
      identityBvh.worldRays = rays;
      identityBvh.instance = &inst;
      identityReady = true;
    }
    return identity.get();
  }

  /// The object packet of `inst` for `lanes`, lane l limited to tfar(l); equal, lane by lane, to
  /// objectRayFor(inst, rays[l], tfar(l)). For accelerators other than BvhAccel (see bvhPacket).
  template <class Tfar>
  ObjectRayPacket& objectPacket(const InstanceRecord& inst, unsigned lanes, const Tfar& tfar) {
    if (!inst.identity) {
      float limits[kRayPacketSize];
      for (unsigned m = lanes; m != 0; m &= m - 1) {
        const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
        limits[l] = tfar(l);
      }
      mapPacketToObject(inst, rays, lanes, limits, mapped.get());
      return mapped.get();
    }
    ObjectRayPacket& packet = identityPacket(inst);
    for (unsigned m = identityBvh.unmappedLanes; m != 0; m &= m - 1)
      BvhAccel::packetLane(packet, identityBvh, static_cast<unsigned>(__builtin_ctz(m)));
    for (unsigned m = lanes; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      ObjectRay& r = packet.rays[l];
      r.tfar = tfar(l);
      r.instanceId = inst.instanceId;
      r.objectId = inst.objectId;
    }
    return packet;
  }

  /// The object packet of BvhAccel instance `inst` and its loaded form, lane l limited to
  /// world.tfar[l] (`world` holds the walk's box rays, whose tfar is each lane's closest hit so
  /// far, or the ray's tfar for any hits): the identity packet shared by identity instances with
  /// the walk's box rows, or a transformed instance's own (loadTransformedPacket). The lanes'
  /// object rays are made only when a test reads one.
  std::pair<ObjectRayPacket*, BvhPacketRays*> bvhPacket(const InstanceRecord& inst, unsigned lanes,
                                                        const PacketBoxRays& world) {
    if (!inst.identity) {
      loadTransformedPacket(inst, rays, lanes, world.tfar, *kernels, mapped.get(), transformedBvh);
      return {&mapped.get(), &transformedBvh};
    }
    ObjectRayPacket& packet = identityPacket(inst);
    // Every lane at once, the walk's lanes outside `lanes` included: their tfar is their own
    // limit too, and the rest are never read. Lane by lane over `lanes`, with each limit taken
    // from the hit and the ray, this was 4% of a kitchen packet's instructions.
    for (unsigned l = 0; l < kRayPacketSize; ++l) {
      ObjectRay& r = packet.rays[l];
      r.tfar = world.tfar[l];
      r.instanceId = inst.instanceId;
      r.objectId = inst.objectId;
    }
    if (!identityBvhReady) {
      BvhAccel::loadIdentityPacket(world, walkLanes, identityFiltered, *kernels, identityBvh);
      identityBvhReady = true;
    } else {
      std::copy(std::begin(world.tfar), std::end(world.tfar), identityBvh.box.tfar);
    }
    return {&packet, &identityBvh};
  }

  /// The closest hits of `lanes` in the instance (or subtree of one) `ref` refers to; lowers
  /// boxRays.tfar of the lanes that found a closer hit.
  void intersectRef(const Ref& ref, unsigned lanes, PacketBoxRays& boxRays) {
    const InstanceRecord& inst = top->instances_[ref.instance];
    const auto tfar = [&](unsigned l) {
      return hits[l].t < rays[l].tfar ? hits[l].t : rays[l].tfar;
    };
    unsigned changed = 0;
    if (isBvhAccel(*inst.accel)) {
      const auto [packet, loaded] = bvhPacket(inst, lanes, boxRays);
      const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
      changed = bvh.intersectLoadedPacket(*packet, *loaded, lanes & loaded->coherent, hits, *ctx,
                                          ref.subtree());
      changed |=
          intersectIncoherent(bvh, ref.subtree(), lanes & ~loaded->coherent, *packet, *loaded);
    } else {
      changed = inst.accel->intersectPacket(objectPacket(inst, lanes, tfar), lanes, hits, *ctx);
    }
    lowerTfar(changed, boxRays);
  }

  /// Lanes the packet test does not take walk the same subtree alone: in a transformed
  /// instance, those with other object-space direction signs than the first (the identity
  /// packet loads every lane of the walk). Returns the lanes whose hit changed.
  unsigned intersectIncoherent(const BvhAccel& bvh, const BvhSubtree& root, unsigned lanes,
                               ObjectRayPacket& packet, BvhPacketRays& loaded) {
    unsigned changed = 0;
    for (unsigned m = lanes; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      if (bvh.intersectSubtree(BvhAccel::packetLane(packet, loaded, l), hits[l], root.child,
                               root.count, *ctx))
        changed |= 1u << l;
    }
    return changed;
  }

  /// Lowers boxRays.tfar of the lanes `changed` to their hits.
  void lowerTfar(unsigned changed, PacketBoxRays& boxRays) const {
    for (unsigned m = changed; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      boxRays.tfar[l] = std::min(boxRays.tfar[l], hits[l].t);
    }
  }

  static unsigned intersectLeaf(void* user, std::uint32_t first, std::uint32_t count,
                                unsigned lanes, PacketBoxRays& boxRays) {
    auto& w = *static_cast<TopLevelPacketWalk*>(user);
    for (std::uint32_t k = first; k < first + count; ++k)
      w.intersectRef(w.top->refs_[k], lanes, boxRays);
    return 0;
  }

  /// The lanes of `lanes` that the instance (or subtree of one) `ref` refers to occludes.
  unsigned occludedRef(const Ref& ref, unsigned lanes, PacketBoxRays& boxRays) {
    const InstanceRecord& inst = top->instances_[ref.instance];
    const auto tfar = [&](unsigned l) { return rays[l].tfar; };
    unsigned found = 0;
    if (isBvhAccel(*inst.accel)) {
      const auto [packet, loaded] = bvhPacket(inst, lanes, boxRays);
      const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
      found =
          bvh.occludedLoadedPacket(*packet, *loaded, lanes & loaded->coherent, *ctx, ref.subtree());
      found |= occludedIncoherent(bvh, ref.subtree(), lanes & ~loaded->coherent, *packet, *loaded);
    } else {
      found = inst.accel->occludedPacket(objectPacket(inst, lanes, tfar), lanes, *ctx);
    }
    if (found != 0) top->rememberOccluder(ref.instance, *ctx);
    return found;
  }

  /// As in intersectIncoherent: lanes outside the packet test walk the subtree alone.
  unsigned occludedIncoherent(const BvhAccel& bvh, const BvhSubtree& root, unsigned lanes,
                              ObjectRayPacket& packet, BvhPacketRays& loaded) {
    unsigned found = 0;
    for (unsigned m = lanes; m != 0; m &= m - 1) {
      const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
      if (bvh.occludedSubtree(BvhAccel::packetLane(packet, loaded, l), root.child, root.count,
                              *ctx))
        found |= 1u << l;
    }
    return found;
  }

  static unsigned occludedLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                               PacketBoxRays& boxRays) {
    auto& w = *static_cast<TopLevelPacketWalk*>(user);
    unsigned blocked = 0;
    for (std::uint32_t k = first; k < first + count && lanes != 0; ++k) {
      const unsigned found = w.occludedRef(w.top->refs_[k], lanes, boxRays);
      blocked |= found;
      lanes &= ~found;
    }
    return blocked;
  }

  static unsigned intersectSingle(void* user, std::uint32_t child, unsigned lane,
                                  PacketBoxRays& boxRays) {
    auto& w = *static_cast<TopLevelPacketWalk*>(user);
    const Ray& ray = w.rays[lane];
    Hit& hit = w.hits[lane];
    float tfar = boxRays.tfar[lane];
    InstanceEntry enter(ray);
    const Bvh4Ray box(ray.origin, ray.direction, ray.tnear);
    traverseBvh4From<false>(
        w.top->bvh_.nodes, child, 0, box, tfar, w.ctx->nodeVisits,
        [&](std::uint32_t first, std::uint32_t count) {
          bool found = false;
          for (std::uint32_t k = first; k < first + count; ++k) {
            if (w.top->intersectRef(w.top->refs_[k], enter, ray, box, hit, *w.ctx)) {
              tfar = std::min(tfar, hit.t);
              found = true;
            }
          }
          return found;
        });
    boxRays.tfar[lane] = tfar;
    return 0;
  }

  static unsigned occludedSingle(void* user, std::uint32_t child, unsigned lane, PacketBoxRays&) {
    auto& w = *static_cast<TopLevelPacketWalk*>(user);
    const Ray& ray = w.rays[lane];
    InstanceEntry enter(ray);
    const Bvh4Ray box(ray.origin, ray.direction, ray.tnear);
    return traverseBvh4From<true>(
               w.top->bvh_.nodes, child, 0, box, ray.tfar, w.ctx->nodeVisits,
               [&](std::uint32_t first, std::uint32_t count) {
                 for (std::uint32_t k = first; k < first + count; ++k)
                   if (w.top->occludedRef(w.top->refs_[k], enter, ray, box, *w.ctx)) return true;
                 return false;
               })
               ? 1u
               : 0u;
  }

  /// Loads the world rays of `lanes` whose direction signs match the first traceable lane's;
  /// leaves the lanes whose rays are not traceable out of `lanes`.
  unsigned load(unsigned& lanes, PacketBoxRays& boxRays) {
    walkLanes = kernels->loadBoxRays(rays, hits, lanes, boxRays);
    return walkLanes;
  }

  /// Walks the traceable lanes of `lanes` of `rays` group by group: each group of equal
  /// direction signs walks as a packet of its own with the query's callbacks (`anyHit`, `leaf`,
  /// `single`). Returns what the walks return (any hit: the lanes found occluded) and leaves in
  /// `lanes` those still to be traced alone: the groups too small for a packet, and what remains
  /// below kMinPacketLanes (not yet checked for traceability).
  static unsigned walkGroups(const TopLevelBvh* top, const Ray* rays, Hit* hits,
                             TraversalContext& ctx, bool anyHit, PacketLeafFn leaf,
                             PacketSingleFn single, unsigned& lanes) {
    unsigned alone = 0, found = 0;
    const PacketKernels& kernels = activePacketKernels();
    while (laneCount(lanes) >= kMinPacketLanes) {
      TopLevelPacketWalk walk(top, rays, hits, &ctx, &kernels);
      PacketBoxRays boxRays;
      unsigned group = walk.load(lanes, boxRays);
      lanes &= ~group;
      if (group == 0) break;
      if (laneCount(group) < kMinPacketLanes) {
        alone |= group;
        continue;
      }
      // Packets from outside the top level's box test that box first, as single rays do: its
      // lanes that miss it are done (no hit, not occluded), and a packet all of whose lanes
      // miss (most of those from a camera framing a scene's bounds) skips the walk and its
      // set-up. One thread, 640x480, from a camera framing the BART scenes' bounds, alternating
      // processes: museum 0.99 -> 1.02-1.03 of rtcIntersect8's speed, kitchen 2-4% and robots
      // 3-4% less time; from the files' cameras, whose origins lie inside, unchanged.
      if (!top->bvh_.bounds.contains(rays[__builtin_ctz(group)].origin)) {
        group = kernels.meetsOneBox(top->outerBounds_, boxRays, group);
        if (group == 0) continue;
      }
      found |= kernels.traverse(top->bvh_.nodes.data(), 0, 0, boxRays, group, anyHit, leaf, single,
                                &walk, ctx.nodeVisits);
    }
    lanes |= alone;
    return found;
  }
};

/// Two neighbouring packets walking the top level as one pair (PairTraverseFn), each half with
/// its own TopLevelPacketWalk (its loaded rows, its identity and transformed packets). A BvhAccel
/// instance that both halves enter is walked as a pair too (BvhAccel::intersectLoadedPair).
struct TopLevelPairWalk {
  TopLevelPacketWalk* half[2];

  static void intersectLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                            PacketBoxRays* const (&rays)[2]) {
    auto& p = *static_cast<TopLevelPairWalk*>(user);
    const unsigned halfLanes[2] = {lanes & kAllLanes, lanes >> kPacketLanes};
    const TopLevelBvh* top = p.half[0]->top;
    for (std::uint32_t k = first; k < first + count; ++k) {
      const TopLevelBvh::Ref& ref = top->refs_[k];
      const InstanceRecord& inst = top->instances_[ref.instance];
      if (halfLanes[0] == 0 || halfLanes[1] == 0 || !isBvhAccel(*inst.accel)) {
        for (unsigned h = 0; h < 2; ++h)
          if (halfLanes[h] != 0) p.half[h]->intersectRef(ref, halfLanes[h], *rays[h]);
        continue;
      }
      const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
      BvhAccel::LoadedHalf loaded[2];
      for (unsigned h = 0; h < 2; ++h) {
        const auto [packet, rows] = p.half[h]->bvhPacket(inst, halfLanes[h], *rays[h]);
        loaded[h] = {packet, rows, halfLanes[h] & rows->coherent, p.half[h]->hits};
      }
      unsigned changed[2];
      bvh.intersectLoadedPair(loaded, *p.half[0]->ctx, ref.subtree(), changed);
      for (unsigned h = 0; h < 2; ++h) {
        changed[h] |= p.half[h]->intersectIncoherent(bvh, ref.subtree(),
                                                     halfLanes[h] & ~loaded[h].rays->coherent,
                                                     *loaded[h].packet, *loaded[h].rays);
        p.half[h]->lowerTfar(changed[h], *rays[h]);
      }
    }
  }

  static unsigned occludedLeaf(void* user, std::uint32_t first, std::uint32_t count, unsigned lanes,
                               PacketBoxRays* const (&rays)[2]) {
    auto& p = *static_cast<TopLevelPairWalk*>(user);
    unsigned halfLanes[2] = {lanes & kAllLanes, lanes >> kPacketLanes};
    const TopLevelBvh* top = p.half[0]->top;
    unsigned blocked[2] = {0, 0};
    for (std::uint32_t k = first; k < first + count && (halfLanes[0] | halfLanes[1]) != 0; ++k) {
      const TopLevelBvh::Ref& ref = top->refs_[k];
      const InstanceRecord& inst = top->instances_[ref.instance];
      unsigned found[2] = {0, 0};
      if (halfLanes[0] == 0 || halfLanes[1] == 0 || !isBvhAccel(*inst.accel)) {
        for (unsigned h = 0; h < 2; ++h)
          if (halfLanes[h] != 0) found[h] = p.half[h]->occludedRef(ref, halfLanes[h], *rays[h]);
      } else {
        const auto& bvh = static_cast<const BvhAccel&>(*inst.accel);
        BvhAccel::LoadedHalf loaded[2];
        for (unsigned h = 0; h < 2; ++h) {
          const auto [packet, rows] = p.half[h]->bvhPacket(inst, halfLanes[h], *rays[h]);
          loaded[h] = {packet, rows, halfLanes[h] & rows->coherent, nullptr};
        }
        bvh.occludedLoadedPair(loaded, *p.half[0]->ctx, ref.subtree(), found);
        for (unsigned h = 0; h < 2; ++h)
          found[h] |= p.half[h]->occludedIncoherent(bvh, ref.subtree(),
                                                    halfLanes[h] & ~loaded[h].rays->coherent,
                                                    *loaded[h].packet, *loaded[h].rays);
        if ((found[0] | found[1]) != 0) top->rememberOccluder(ref.instance, *p.half[0]->ctx);
      }
      for (unsigned h = 0; h < 2; ++h) {
        blocked[h] |= found[h];
        halfLanes[h] &= ~found[h];
      }
    }
    return blocked[0] | (blocked[1] << kPacketLanes);
  }

  static unsigned occludedSingle(void* user, std::uint32_t child, unsigned lane,
                                 PacketBoxRays* const (&rays)[2]) {
    auto& p = *static_cast<TopLevelPairWalk*>(user);
    const unsigned h = lane / kPacketLanes;
    return TopLevelPacketWalk::occludedSingle(p.half[h], child, lane % kPacketLanes, *rays[h]);
  }

  static void intersectSingle(void* user, std::uint32_t child, unsigned lane,
                              PacketBoxRays* const (&rays)[2]) {
    auto& p = *static_cast<TopLevelPairWalk*>(user);
    const unsigned h = lane / kPacketLanes;
    TopLevelPacketWalk::intersectSingle(p.half[h], child, lane % kPacketLanes, *rays[h]);
  }
};

// Lanes whose direction signs differ cannot share box rows (shadow rays towards a light among
// their origins, say): each group of equal signs walks as a packet of its own, and groups too
// small for one go lane by lane.

void TopLevelBvh::intersectPacket(const Ray* rays, unsigned lanes, Hit* hits,
                                  TraversalContext& ctx) const {
  if (lanes == 0 || bvh_.nodes.empty()) return;
  TopLevelPacketWalk::walkGroups(this, rays, hits, ctx, false, &TopLevelPacketWalk::intersectLeaf,
                                 &TopLevelPacketWalk::intersectSingle, lanes);
  TopLevelAccel::intersectPacket(rays, lanes, hits, ctx);
}

/// The set-up of a pair walk over the top level: each half's walk state, box rays and group.
struct TopLevelPairLoad {
  TopLevelPairLoad(const TopLevelBvh* top_, const Ray* rays, Hit* hits, TraversalContext& ctx,
                   const PacketKernels& kernels_)
      : top(top_),
        kernels(kernels_),
        walk{{top_, rays, hits, &ctx, &kernels_},
             {top_, rays + kPacketLanes, hits != nullptr ? hits + kPacketLanes : nullptr, &ctx,
              &kernels_}} {}

  const TopLevelBvh* top;
  const PacketKernels& kernels;
  TopLevelPacketWalk walk[2];
  PacketBoxRays boxRays[2];
  /// Per half: the lanes that walk as the pair's (those that miss the top level's box, for rays
  /// from outside it, left out as walkGroups leaves them out), and those left for the packet
  /// query of the half (other signs than its first traceable lane).
  unsigned group[2] = {0, 0}, rest[2] = {0, 0};

  /// Loads the halves of `lanes`; true when they walk as a pair, else every group is back in
  /// `rest`.
  bool load(unsigned lanes) {
    for (unsigned h = 0; h < 2; ++h) {
      rest[h] = (lanes >> (kPacketLanes * h)) & kAllLanes;
      group[h] = rest[h] != 0 ? walk[h].load(rest[h], boxRays[h]) : 0;
      rest[h] &= ~group[h];
      if (group[h] != 0 && !top->bvh_.bounds.contains(walk[h].rays[__builtin_ctz(group[h])].origin))
        group[h] = kernels.meetsOneBox(top->outerBounds_, boxRays[h], group[h]);
    }
    if (group[0] != 0 && group[1] != 0 && boxRays[0].signs == boxRays[1].signs &&
        laneCount(group[0]) + laneCount(group[1]) >= 2 * kMinPacketLanes)
      return true;
    rest[0] |= group[0];
    rest[1] |= group[1];
    return false;
  }

  /// The box rays of both halves, as the pair kernels take them.
  PacketBoxRays* const boxPointers[2] = {&boxRays[0], &boxRays[1]};
};

void TopLevelBvh::intersectPacketPair(const Ray* rays, unsigned lanes, Hit* hits,
                                      TraversalContext& ctx) const {
  const PacketKernels& kernels = activePacketKernels();
  if (lanes == 0 || bvh_.nodes.empty() || kernels.traversePair == nullptr) {
    TopLevelAccel::intersectPacketPair(rays, lanes, hits, ctx);
    return;
  }
  TopLevelPairLoad pair(this, rays, hits, ctx, kernels);
  if (pair.load(lanes)) {
    TopLevelPairWalk walk{{&pair.walk[0], &pair.walk[1]}};
    kernels.traversePair(bvh_.nodes.data(), 0, 0, pair.boxPointers,
                         pair.group[0] | (pair.group[1] << kPacketLanes),
                         &TopLevelPairWalk::intersectLeaf, &TopLevelPairWalk::intersectSingle,
                         &walk, ctx.nodeVisits);
  }
  for (unsigned h = 0; h < 2; ++h)
    if (pair.rest[h] != 0)
      intersectPacket(rays + kPacketLanes * h, pair.rest[h], hits + kPacketLanes * h, ctx);
}

unsigned TopLevelBvh::hintedLanes(const Ray* rays, unsigned lanes, TraversalContext& ctx) const {
  if (ctx.occluder.build != buildId_) return 0;
  unsigned hinted = 0;
  for (unsigned m = lanes; m != 0; m &= m - 1) {
    const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
    if (isTraceable(rays[l]) && occludedByHint(rays[l], ctx)) hinted |= 1u << l;
  }
  return hinted;
}

unsigned TopLevelBvh::occludedWalked(const Ray* rays, unsigned lanes, TraversalContext& ctx) const {
  const unsigned blocked = TopLevelPacketWalk::walkGroups(
      this, rays, nullptr, ctx, true, &TopLevelPacketWalk::occludedLeaf,
      &TopLevelPacketWalk::occludedSingle, lanes);
  return blocked | TopLevelAccel::occludedPacket(rays, lanes, ctx);
}

unsigned TopLevelBvh::occludedPacketPair(const Ray* rays, unsigned lanes,
                                         TraversalContext& ctx) const {
  const PacketKernels& kernels = activePacketKernels();
  if (lanes == 0 || bvh_.nodes.empty() || kernels.occludedPair == nullptr)
    return TopLevelAccel::occludedPacketPair(rays, lanes, ctx);
  // Lanes the hint's triangle blocks are done (see occluded); the rest walk.
  const unsigned hinted = hintedLanes(rays, lanes, ctx);
  lanes &= ~hinted;
  if (lanes == 0) return hinted;
  TopLevelPairLoad pair(this, rays, nullptr, ctx, kernels);
  unsigned blocked = hinted;
  if (pair.load(lanes)) {
    TopLevelPairWalk walk{{&pair.walk[0], &pair.walk[1]}};
    blocked |= kernels.occludedPair(
        bvh_.nodes.data(), 0, 0, pair.boxPointers, pair.group[0] | (pair.group[1] << kPacketLanes),
        &TopLevelPairWalk::occludedLeaf, &TopLevelPairWalk::occludedSingle, &walk, ctx.nodeVisits);
  }
  for (unsigned h = 0; h < 2; ++h)
    if (pair.rest[h] != 0)
      blocked |= occludedWalked(rays + kPacketLanes * h, pair.rest[h], ctx) << (kPacketLanes * h);
  return blocked;
}

unsigned TopLevelBvh::occludedPacket(const Ray* rays, unsigned lanes, TraversalContext& ctx) const {
  if (lanes == 0 || bvh_.nodes.empty()) return 0;
  // Lanes the hint's triangle blocks are done (see occluded); the rest walk.
  const unsigned hinted = hintedLanes(rays, lanes, ctx);
  lanes &= ~hinted;
  if (lanes == 0) return hinted;
  return hinted | occludedWalked(rays, lanes, ctx);
}

}  // namespace tg::detail
