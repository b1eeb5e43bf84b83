/// @file TopLevelAccel.h
/// The top-level accelerator over instances, and the instance record it traverses.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/ObjectAccel.h"

namespace tg {

/// What the top level needs of one instance: its object's accelerator, both matrices
/// (stored in float, computed in double) and its conservative world bounds.
struct InstanceRecord {
  /// The object's accelerator (built).
  const ObjectAccel* accel = nullptr;
  /// World to object, inverted in double: rays are mapped into object space with it (see
  /// intersectInstance), and hit normals back to world space (Scene::fillGeometricNormal).
  Affine3d worldToObjectD;
  /// Conservative world bounds of the object's triangles.
  Box3f worldBounds;
  /// Id written into hits.
  std::uint32_t instanceId = kInvalidId;
  /// Id written into hits.
  std::uint32_t objectId = kInvalidId;
  bool identity = false;  ///< objectToWorld is exactly the identity: skip the ray transform
};

/// Which top-level accelerator to build.
enum class TopLevelKind : std::uint8_t {
  KdTree,  ///< the paper's Algorithm 1 kd-tree over instance bounds
  Bvh,     ///< 4-wide binned-SAH BVH over instance bounds, rebuilt in parallel
};

/// Statistics of a top-level build.
struct TopLevelStats {
  /// Instances built over.
  std::size_t instances = 0;
  /// Inner nodes + leaves.
  std::size_t nodes = 0;
  /// Leaves, empty ones included.
  std::size_t leaves = 0;
  /// Depth of the deepest leaf (root: 0).
  std::size_t maxDepth = 0;
  /// Leaf entries: one per instance, or one per subtree for an instance the BVH top level
  /// enters by subtree (TopLevelKind::Bvh, static geometry in scenes of up to 1024 instances).
  std::size_t references = 0;
  /// Wall time of the build.
  double buildMs = 0.0;
};

/// A top-level accelerator: built over instance records, traversed with world-space rays.
class TopLevelAccel {
 public:
  virtual ~TopLevelAccel() = default;
  TopLevelAccel() = default;
  TopLevelAccel(const TopLevelAccel&) = delete;
  TopLevelAccel& operator=(const TopLevelAccel&) = delete;

  /// Which accelerator this is.
  virtual TopLevelKind kind() const = 0;
  /// Rebuilds over `instances`; the records must stay alive and unchanged until the next build.
  virtual void build(std::span<const InstanceRecord> instances) = 0;
  /// Closest hit of a world ray over all instances (updates hit; world normal not filled).
  virtual bool intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const = 0;
  /// Any hit of a world ray in [tnear, tfar].
  virtual bool occluded(const Ray& ray, TraversalContext& ctx) const = 0;
  /// Closest hits of the lanes in `lanes` of `rays` (kRayPacketSize entries): for each lane i
  /// whose ray is traceable (isTraceable), exactly what intersect(rays[i], hits[i], ctx) gives;
  /// the hits of the other lanes are left as they are. The default traces lane by lane.
  virtual void intersectPacket(const Ray* rays, unsigned lanes, Hit* hits,
                               TraversalContext& ctx) const;
  /// intersectPacket for two neighbouring packets at once: `rays` and `hits` hold
  /// 2 * kRayPacketSize entries, bit kRayPacketSize * h + l of `lanes` is lane l of packet h.
  /// Same answers as intersectPacket on each packet; an accelerator whose packets share their
  /// walk (one node test for the lanes of both) overrides it. The default traces packet by
  /// packet.
  virtual void intersectPacketPair(const Ray* rays, unsigned lanes, Hit* hits,
                                   TraversalContext& ctx) const;
  /// Any-hit counterpart of intersectPacket: returns the lanes that are occluded (never one
  /// whose ray is not traceable).
  virtual unsigned occludedPacket(const Ray* rays, unsigned lanes, TraversalContext& ctx) const;
  /// Any-hit counterpart of intersectPacketPair: returns the lanes (bit kRayPacketSize * h + l
  /// for lane l of packet h) that are occluded. The default traces packet by packet.
  virtual unsigned occludedPacketPair(const Ray* rays, unsigned lanes, TraversalContext& ctx) const;
  /// Statistics of the last build.
  virtual const TopLevelStats& stats() const = 0;
};

/// Name used in statistics and benchmark rows.
std::string_view topLevelKindName(TopLevelKind kind);
/// Creates an (unbuilt) top-level accelerator of the given kind.
std::unique_ptr<TopLevelAccel> createTopLevelAccel(TopLevelKind kind);

/// Maps a world ray into the instance's object space. The direction is not renormalised, so t
/// stays comparable across instances. The mapping is done in double with the double inverse
/// and then rounded once: a float 3x4 inverse would round the origin at the magnitude of the
/// instance's translation, and t would inherit that error (hard case 7).
inline ObjectRay objectRayFor(const InstanceRecord& inst, const Ray& ray, float tfar) {
  if (inst.identity)
    return ObjectRay(ray.origin, ray.direction, ray.tnear, tfar, inst.instanceId, inst.objectId);
  return ObjectRay(inst.worldToObjectD.transformPoint(Vec3d(ray.origin)),
                   inst.worldToObjectD.transformVector(Vec3d(ray.direction)), ray.tnear, tfar,
                   inst.instanceId, inst.objectId);
}

/// Intersects one instance's object with a world ray. Shared by every top-level accelerator.
inline bool intersectInstance(const InstanceRecord& inst, const Ray& ray, Hit& hit,
                              TraversalContext& ctx) {
  ObjectRay objectRay = objectRayFor(inst, ray, hit.t < ray.tfar ? hit.t : ray.tfar);
  return inst.accel->intersect(objectRay, hit, ctx);
}

/// Any-hit counterpart of intersectInstance.
inline bool occludedInstance(const InstanceRecord& inst, const Ray& ray, TraversalContext& ctx) {
  return inst.accel->occluded(objectRayFor(inst, ray, ray.tfar), ctx);
}

/// The instances one world ray enters during one top-level walk. Every identity instance (all
/// static geometry is one, split into chunks) sees the world ray itself, so its object ray,
/// with the shear constants and reciprocals that cost divisions, is made once, at the first
/// identity instance entered, and only its tfar and ids change from one to the next. Answers
/// equal intersectInstance's and occludedInstance's.
class InstanceEntry {
 public:
  /// For `ray`, which must outlive the entry.
  explicit InstanceEntry(const Ray& ray) : ray_(ray) {}

  /// intersectInstance(inst, ray, hit, ctx).
  bool intersect(const InstanceRecord& inst, Hit& hit, TraversalContext& ctx) {
    if (!inst.identity) return intersectInstance(inst, ray_, hit, ctx);
    return inst.accel->intersect(identityRay(inst, hit.t < ray_.tfar ? hit.t : ray_.tfar), hit,
                                 ctx);
  }
  /// occludedInstance(inst, ray, ctx).
  bool occluded(const InstanceRecord& inst, TraversalContext& ctx) {
    if (!inst.identity) return occludedInstance(inst, ray_, ctx);
    return inst.accel->occluded(identityRay(inst, ray_.tfar), ctx);
  }

  /// objectRayFor(inst, ray, tfar) for an identity instance: accelerators change only tfar of
  /// the rays they are given (ObjectAccel::intersect), so the rest is still the world ray's.
  /// For top levels that enter parts of an identity instance's accelerator themselves.
  ObjectRay& identityRay(const InstanceRecord& inst, float tfar) {
    if (!identity_) {
      identity_.emplace(ray_.origin, ray_.direction, ray_.tnear, tfar, inst.instanceId,
                        inst.objectId);
    } else {
      identity_->tfar = tfar;
      identity_->instanceId = inst.instanceId;
      identity_->objectId = inst.objectId;
    }
    return *identity_;
  }

 private:
  const Ray& ray_;
  /// Made at the first identity instance (std::optional: rays that enter none pay nothing).
  std::optional<ObjectRay> identity_;
};

}  // namespace tg
