/// @file ObjectAccel.h
/// The interface every object-level accelerator implements (the paper's per-object kd-trees
/// today, wide BVHs later), so that a new kind drops in without touching its callers.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/WatertightTriangle.h"

namespace tg {

/// Which object accelerator to build.
enum class AccelKind : std::uint8_t {
  SahKdTree,   ///< high-quality SAH kd-tree, O(n log n) build (static and rigid objects)
  FastKdTree,  ///< the paper's fast kd-tree for deforming objects (spatial median splits)
  Bvh,         ///< 4-wide BVH from a parallel binned-SAH builder (static and rigid objects)
  BvhFast,     ///< 4-wide BVH from a Morton-code (linear) builder, refittable (deforming objects)
};

/// Name used in statistics and benchmark rows ("sah-kd", "fast-kd", "bvh", "bvh-fast").
std::string_view accelKindName(AccelKind kind);

/// What a build produced, for statistics and benchmarks.
struct BuildStats {
  std::size_t triangles = 0;   ///< triangles in the mesh
  std::size_t degenerate = 0;  ///< zero-area triangles left out of the tree (never hit)
  std::size_t nodes = 0;       ///< inner nodes + leaves
  /// Leaves, empty ones included.
  std::size_t leaves = 0;
  /// Leaves without references.
  std::size_t emptyLeaves = 0;
  std::size_t primReferences = 0;  ///< triangle references in leaves (>= triangles with splits)
  /// Nodes of an eight-wide copy of the tree that single rays walk (SAH BVHs on CPUs with
  /// AVX2); 0 without one.
  std::size_t wideNodes = 0;
  /// Depth of the deepest leaf (root: 0).
  std::size_t maxDepth = 0;
  std::size_t bytes = 0;  ///< memory held by the accelerator (nodes, refs, triangle copy)
  /// Wall time of the build (or of the refit, when `refitted`).
  double buildMs = 0.0;
  /// True when the last update refitted the boxes of the existing tree instead of rebuilding.
  bool refitted = false;
  /// Surface-area-heuristic cost of the current tree, in units of one node visit per ray that
  /// hits the root box (0 when the accelerator does not compute it). Refits keep the topology
  /// of the tree, so this grows as the geometry drifts away from the state it was built for.
  double sahCost = 0.0;
  /// sahCost right after the last full build: sahCost / buildSahCost says how much refits have
  /// degraded the tree, which is what a caller weighs to choose refit or rebuild.
  double buildSahCost = 0.0;
};

/// Small direct-mapped cache of the triangles a ray has already tested in the current object.
///
/// Mailboxing: a triangle referenced by several kd-tree leaves is tested once per ray. The
/// mailbox lives on the tracing thread's stack, one per ray, so threads never share writes
/// (the paper's per-ray-id mailboxes in shared memory would need atomic or per-thread copies).
struct Mailbox {
  /// Number of entries (a power of two: the slot is a hash's top bits).
  static constexpr std::uint32_t kSlots = 16;
  /// Triangle ids tested, or kInvalidId.
  std::uint32_t slots[kSlots];

  /// Forgets every entry (before each ray and object).
  void clear() {
    for (std::uint32_t& s : slots) s = kInvalidId;
  }
  /// True when `prim` was already tested; otherwise remembers it and returns false.
  bool testAndSet(std::uint32_t prim) {
    std::uint32_t& s = slots[(prim * 2654435761u) >> 28];
    if (s == prim) return true;
    s = prim;
    return false;
  }
};

/// A ray in an object's space, with its per-ray constants. `tfar` shrinks as hits are found.
struct ObjectRay {
  WatertightRay wt;        ///< origin, direction, tnear and shear constants
  Vec3f inverseDirection;  ///< 1/direction per component (+-inf for +-0 components)
  /// Largest t that counts; lowered to each closer hit.
  float tfar = kInfinity;
  /// Instance the ray was mapped through, written into hits.
  std::uint32_t instanceId = kInvalidId;
  /// Object being traversed, written into hits.
  std::uint32_t objectId = kInvalidId;

  ObjectRay() = default;
  /// From a float object-space ray.
  ObjectRay(const Vec3f& origin, const Vec3f& direction, float tnear, float tfar_,
            std::uint32_t instance, std::uint32_t object)
      : wt(origin, direction, tnear),
        inverseDirection(reciprocals(direction)),
        tfar(tfar_),
        instanceId(instance),
        objectId(object) {}
  /// From a double-precision object-space ray (see WatertightRay).
  ObjectRay(const Vec3d& origin, const Vec3d& direction, float tnear, float tfar_,
            std::uint32_t instance, std::uint32_t object)
      : wt(origin, direction, tnear),
        inverseDirection(reciprocals(wt.direction)),
        tfar(tfar_),
        instanceId(instance),
        objectId(object) {}
};

/// Rays per packet in the packet queries (ObjectAccel::intersectPacket, TopLevelAccel and the
/// Scene's queries over spans of rays); lane i of a packet is bit i of a lane mask.
inline constexpr unsigned kRayPacketSize = 8;

/// Up to kRayPacketSize object-space rays traced together; a lane mask says which are live.
struct ObjectRayPacket {
  /// One ray per lane.
  ObjectRay rays[kRayPacketSize];
};

/// Per-query scratch state owned by the thread that traces the ray.
struct TraversalContext {
  Mailbox mailbox;                  ///< triangles tested in the current object
  Mailbox instanceMailbox;          ///< instances tested by the top level for this ray
  std::uint64_t triangleTests = 0;  ///< statistics: watertight tests performed
  std::uint64_t nodeVisits = 0;     ///< statistics: accelerator nodes visited
  /// The triangle that blocked the last occluded ray, which the next any-hit query of the same
  /// top-level build tests before its walk: shadow rays of neighbouring pixels towards one
  /// light are mostly blocked by the same triangle. Only a hint: a query answers "occluded"
  /// from it only when that triangle's own exact test says so, and the walk would then have
  /// found the ray occluded too, so answers never depend on it.
  ///
  /// Where neighbouring rays are blocked by different triangles (a cloud of small objects), the
  /// hint's test costs more than its rare successes save, so the hint keeps its recent success
  /// rate and, while that is low, is tested on one query in a few only (enough to notice when it
  /// pays again).
  struct OccluderHint {
    std::uint64_t build = 0;      ///< the top-level build it refers to (0: none)
    std::uint32_t instance = 0;   ///< index of the instance record in that build
    std::uint32_t primitive = 0;  ///< the object accelerator's own index of the triangle
    /// Share of the recent hint tests that found the ray occluded, in 1/65536 (a moving average
    /// over about sixteen tests; starts at one half).
    std::uint16_t successRate = 32768;
    /// Queries that left the hint untested since its last test (while successRate is low).
    std::uint16_t skipped = 0;
  };
  /// The hint of the last occluded ray (see OccluderHint).
  OccluderHint occluder;
  /// Written by object accelerators' any-hit queries: their own index of the triangle that
  /// blocked the ray (ObjectAccel::occludedByPrimitive takes it back).
  std::uint32_t occludingPrimitive = 0;
  /// Whether the span queries (Scene::intersect and Scene::occluded over spans) walk each two
  /// full neighbouring packets as one, where the active packet kernels can (sixteen lanes per
  /// node test). Answers are the same either way; false walks every packet alone, which is what
  /// benchmarks compare against.
  bool pairPackets = true;
};

/// An object-level accelerator over one triangle mesh, in the mesh's own (object) space.
class ObjectAccel {
 public:
  virtual ~ObjectAccel() = default;
  ObjectAccel() = default;
  ObjectAccel(const ObjectAccel&) = delete;
  ObjectAccel& operator=(const ObjectAccel&) = delete;

  /// Which builder this accelerator uses.
  virtual AccelKind kind() const = 0;
  /// (Re)builds over `mesh`, which must be valid (TriangleMesh::validate). The accelerator keeps
  /// its own copy of the triangles it needs, so the mesh may change afterwards.
  virtual void build(const TriangleMesh& mesh) = 0;
  /// Updates the tree for moved vertices without rebuilding it: keeps the tree's topology and
  /// recomputes its boxes from `mesh` (valid, see build). Returns false, changing nothing, when
  /// the accelerator cannot refit (the default) or when `mesh` has other triangles than the
  /// last build (triangle count or indices differ); the caller then calls build(). After a
  /// refit, stats().refitted is true and stats().sahCost is the refitted tree's cost.
  virtual bool refit(const TriangleMesh& mesh) {
    (void)mesh;
    return false;
  }
  /// Bounds of the non-degenerate triangles (empty box when there are none).
  virtual Box3f bounds() const = 0;
  /// Closest hit: when a triangle is hit at t in [tnear, ray.tfar] and precedes `hit`
  /// (see hitPrecedes), writes t, u, v, primId, instanceId and objectId into `hit` and lowers
  /// ray.tfar. Changes nothing else of `ray` (callers reuse it for the next object). Returns
  /// true when `hit` changed.
  virtual bool intersect(ObjectRay& ray, Hit& hit, TraversalContext& ctx) const = 0;
  /// Any hit in [tnear, tfar].
  virtual bool occluded(const ObjectRay& ray, TraversalContext& ctx) const = 0;
  /// Any hit in [tnear, tfar] of the one triangle `primitive` (the accelerator's own index, as
  /// its any-hit queries leave it in TraversalContext::occludingPrimitive), by the exact test
  /// of those queries, so that true here means occluded() is true too. False for an index out
  /// of range, and always false by default (accelerators that leave no index).
  virtual bool occludedByPrimitive(const ObjectRay& /*ray*/, std::uint32_t /*primitive*/) const {
    return false;
  }
  /// Closest hits of the lanes in `lanes`: for each lane i, exactly what
  /// intersect(packet.rays[i], hits[i], ctx) gives. Returns the lanes whose hit changed.
  /// Accelerators with a packet walk trace lanes whose direction signs agree together and the
  /// others one by one; the default traces every lane alone.
  virtual unsigned intersectPacket(ObjectRayPacket& packet, unsigned lanes, Hit* hits,
                                   TraversalContext& ctx) const;
  /// Any-hit counterpart of intersectPacket: returns the lanes that are occluded.
  virtual unsigned occludedPacket(const ObjectRayPacket& packet, unsigned lanes,
                                  TraversalContext& ctx) const;
  /// What the last build produced.
  virtual const BuildStats& stats() const = 0;
};

/// Creates an (unbuilt) accelerator of the given kind.
std::unique_ptr<ObjectAccel> createObjectAccel(AccelKind kind);

}  // namespace tg
