/// @file Scene.h
/// The engine's C++ API: objects (meshes with their accelerators), instances (an object and an
/// affine matrix) and the two-level structure over them, updated by commit().
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/TopLevelAccel.h"
#include "tracegraph/backend/TriangleMesh.h"

namespace tg {

/// Id of an object (a mesh and its accelerator) in a Scene.
using ObjectId = std::uint32_t;
/// Id of an instance (an object placed by a matrix) in a Scene.
using InstanceId = std::uint32_t;

/// How an object's geometry behaves over time; it chooses the accelerator builder.
enum class ObjectUsage : std::uint8_t {
  Static,     ///< never changes: high-quality (SAH) build
  Rigid,      ///< moved only through its instances' matrices: high-quality build, once
  Deforming,  ///< points change between frames: fast builder, rebuilt (or refitted) on change
};

/// Options fixed when a scene is created.
struct SceneOptions {
  // Defaults: the BVH engine, measured faster to build and to trace than the paper's kd-trees
  // (BENCHMARKS.md); sceneOptionsFor(Engine::KdTree) selects the kd-trees.
  /// Accelerator over the instances.
  TopLevelKind topLevel = TopLevelKind::Bvh;
  /// Accelerator kinds per usage; callers of later engines change these, not their code.
  /// Used for static and rigid objects.
  AccelKind staticAccel = AccelKind::Bvh;
  /// Accelerator of deforming objects. When it supports refitting (AccelKind::BvhFast), commit()
  /// refits instead of rebuilding while the triangles stay the same and the refitted tree's SAH
  /// cost stays within maxRefitCostRatio of its cost at the last full build.
  AccelKind deformingAccel = AccelKind::BvhFast;
  /// Largest sahCost / buildSahCost (see BuildStats) a refitted tree may reach before commit()
  /// rebuilds it instead.
  double maxRefitCostRatio = 1.5;
};

/// The two engines, each a set of accelerators for every usage and the top level.
enum class Engine : std::uint8_t {
  KdTree,  ///< the paper's: SAH kd-trees, the fast kd-tree for deforming objects, Algorithm 1
  Bvh,     ///< wide BVHs: binned-SAH BVH4, the fast BVH with refit, a BVH over instances
};

/// Options that select every accelerator of `engine`.
SceneOptions sceneOptionsFor(Engine engine);

/// Parses "kd" or "bvh" (what tools accept for --accel); false for anything else.
bool parseEngine(std::string_view name, Engine& engine);

/// What one commit() did, for per-frame statistics.
struct CommitStats {
  /// Objects whose accelerator was (re)built from scratch.
  std::size_t objectsRebuilt = 0;
  /// Deforming objects whose accelerator was refitted instead (see SceneOptions::deformingAccel).
  std::size_t objectsRefitted = 0;
  /// Triangles in the objects rebuilt or refitted.
  std::size_t trianglesRebuilt = 0;
  /// Instances created, moved or destroyed.
  std::size_t instancesUpdated = 0;
  /// True when the top level was rebuilt.
  bool topLevelRebuilt = false;
  double rebuildMs = 0.0;   ///< wall time of the (parallel) object builds
  double topLevelMs = 0.0;  ///< wall time of the top-level build
};

/// A two-level ray-tracing scene (Wald, Benthin, Slusallek 2003).
///
/// Edits (create/set/destroy) take effect at the next commit(); queries see the last committed
/// state only, so a half-done edit is never visible. Queries are const and may run on many
/// threads at once; edits and commit() must not overlap queries. Every edit validates its
/// arguments first and throws tg::Error naming the call, leaving the scene unchanged.
class Scene {
 public:
  /// An empty scene built with `options`.
  explicit Scene(const SceneOptions& options = {});
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  /// Adds an object; its accelerator is built at the next commit().
  ObjectId createObject(TriangleMesh mesh, ObjectUsage usage = ObjectUsage::Static);
  /// Replaces an object's mesh (topology may change).
  void setObjectMesh(ObjectId object, TriangleMesh mesh);
  /// Moves an object's points (same count; the usual per-frame update of deforming objects).
  void setObjectPositions(ObjectId object, std::span<const Vec3f> positions);
  /// Removes an object; rejected while instances still use it.
  void destroyObject(ObjectId object);
  /// The mesh as last committed (or as created, before the first commit).
  const TriangleMesh& objectMesh(ObjectId object) const;
  /// The usage given at createObject.
  ObjectUsage objectUsage(ObjectId object) const;
  /// The object's accelerator, or null before its first build.
  const ObjectAccel* objectAccel(ObjectId object) const;

  /// Places an object in the world. The matrix must be finite and non-singular.
  InstanceId createInstance(ObjectId object, const Affine3d& objectToWorld = Affine3d{});
  /// Moves an instance: replaces its object-to-world matrix (same checks as createInstance).
  void setInstanceTransform(InstanceId instance, const Affine3d& objectToWorld);
  /// An instance's object-to-world matrix.
  const Affine3d& instanceTransform(InstanceId instance) const;
  /// The object an instance places.
  ObjectId instanceObject(InstanceId instance) const;
  /// Removes an instance (its object stays).
  void destroyInstance(InstanceId instance);

  /// Builds changed objects (in parallel with oneTBB) and rebuilds the top level when any
  /// instance or object changed.
  CommitStats commit();
  /// True when there are edits not yet committed.
  bool hasPendingChanges() const;

  /// Closest hit in [ray.tnear, ray.tfar]; fills every field of `hit` including the world
  /// normal. Rays with a NaN/Inf origin or a zero/NaN/Inf direction never hit.
  bool intersect(const Ray& ray, Hit& hit) const;
  /// Closest hit, with caller-owned scratch state and statistics.
  bool intersect(const Ray& ray, Hit& hit, TraversalContext& ctx) const;
  /// Any hit in [ray.tnear, ray.tfar].
  bool occluded(const Ray& ray) const;
  /// Any hit, with caller-owned scratch state and statistics.
  bool occluded(const Ray& ray, TraversalContext& ctx) const;

  /// Closest hits of a stream of rays: hits[i] is bit for bit what intersect(rays[i], hits[i],
  /// ctx) gives. Consecutive groups of kRayPacketSize rays are traced as packets (one walk
  /// for all lanes, the box tests of all lanes in one SIMD instruction, see Simd.h); rays whose
  /// direction signs differ from the group's, and groups with too few such rays, fall back to
  /// single rays. Where the active kernels can, each two consecutive full packets walk as one
  /// of 2 * kRayPacketSize lanes (ctx.pairPackets, on by default): order the rays so that they
  /// are neighbours too (the renderer sends 4 x 4 pixel blocks of two 4 x 2 packets). Coherent
  /// streams (a camera tile, shadow rays towards one light) gain most.
  /// Throws tg::Error when the spans differ in size.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits, TraversalContext& ctx) const;
  /// Any hit for a stream of rays: occluded[i] is 1 when occluded(rays[i]) is true, else 0.
  /// Packets as for intersect over spans. Throws tg::Error when the spans differ in size.
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                TraversalContext& ctx) const;

  /// World bounds of the committed scene.
  Box3f bounds() const;
  /// Live objects.
  std::size_t objectCount() const;
  /// Live instances.
  std::size_t instanceCount() const;
  /// Triangles summed over instances (what a flattened copy would hold).
  std::size_t instancedTriangleCount() const;
  /// The top-level accelerator of the committed state.
  const TopLevelAccel& topLevel() const;
  /// The options the scene was created with.
  const SceneOptions& options() const;

  /// Interpolated shading data at a hit (for renderers): world-space shading normal (the
  /// geometric normal when the mesh has none, flipped to its side) and texture coordinates.
  struct SurfaceData {
    Vec3f position;         ///< world-space hit point, origin + t * direction
    Vec3f geometricNormal;  ///< unit, world space
    Vec3f shadingNormal;    ///< unit, world space, interpolated when the mesh has normals
    Vec2f uv;               ///< interpolated, or (u, v) barycentrics when the mesh has none
    /// True when uv comes from the mesh's texture coordinates.
    bool hasUv = false;
  };
  /// Shading data at `hit`, which `ray` found in this scene.
  SurfaceData surfaceAt(const Ray& ray, const Hit& hit) const;
  /// The texture-coordinate area of the hit triangle per unit of its world-space area: how a
  /// footprint on the surface maps into texture space, for mip-mapping. Computed per triangle
  /// at commit in object space and scaled by the instance's area scale (exact for rigid
  /// motions and uniform scales; for non-uniform scales their mean over directions). 0 when
  /// the mesh has no texture coordinates or the triangle is degenerate in either space, or for
  /// an invalid hit.
  float uvAreaPerWorldArea(const Hit& hit) const;

 private:
  /// Fills hit.geometricNormal of a hit found in the committed scene.
  void fillGeometricNormal(Hit& hit) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tg
