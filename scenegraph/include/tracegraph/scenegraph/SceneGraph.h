/// @file SceneGraph.h
/// The public entry of the scene graph: root, clock, animators, classification and the sync
/// of the graph into a backend tg::Scene, plus the maps from hits back to nodes.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/CameraNode.h"
#include "tracegraph/scenegraph/Clock.h"
#include "tracegraph/scenegraph/DynamicsClass.h"
#include "tracegraph/scenegraph/FrameStats.h"
#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/MaterialNode.h"
#include "tracegraph/scenegraph/ShapeNode.h"
#include "tracegraph/scenegraph/SyncDebugStats.h"
#include "tracegraph/scenegraph/SyncOptions.h"
#include "tracegraph/scenegraph/TextureNode.h"

namespace tg {

/// What a backend hit is in graph terms. Pointers stay valid until the next sync().
struct HitInfo {
  const ShapeNode* shape = nullptr;        ///< the mesh node hit
  std::uint32_t triangle = kInvalidId;     ///< triangle index within that mesh
  const MaterialNode* material = nullptr;  ///< current material at the shape, null: default
  const TextureNode* texture = nullptr;    ///< current texture at the shape, or null
  /// The class of the instance hit.
  DynamicsClass dynamics = DynamicsClass::Static;
  /// True when the hit was mapped.
  bool valid() const { return shape != nullptr; }
};

/// A run [primBegin, primEnd) of an instance's triangles that come from one shape
/// occurrence, with the material and texture in effect there.
struct MeshSegment {
  /// First triangle of the run.
  std::uint32_t primBegin = 0;
  /// One past the last triangle of the run.
  std::uint32_t primEnd = 0;
  /// The mesh node the triangles come from.
  const ShapeNode* shape = nullptr;
  const MaterialNode* material = nullptr;  ///< null: default material
  /// Texture in effect there, or null.
  const TextureNode* texture = nullptr;
};

/// A light in world space (position and direction mapped by its current matrix).
struct WorldLight {
  /// The light node.
  const LightNode* node = nullptr;
  /// Its parameters, position and direction in world space.
  LightData data;
};

/// The camera in world space: an orthonormal frame plus the projection parameters.
struct WorldCamera {
  /// The camera node.
  const CameraNode* node = nullptr;
  /// Eye position.
  Vec3f position;
  Vec3f direction{0.0f, 0.0f, -1.0f};  ///< unit view direction
  Vec3f up{0.0f, 1.0f, 0.0f};          ///< unit, perpendicular to direction
  float fov = 0.785398f;               ///< vertical, radians
  /// Near distance along the view ray.
  float hither = 0.01f;
  /// Width / height the camera node asks for.
  float aspect = 1.0f;
};

/// Owns a root node, a clock, the animators feeding the graph, the classifier and the backend
/// scene, and keeps the scene equal to the graph one frame at a time:
///
/// ```
/// sg.setRoot(root);
/// for (;;) { sg.advanceTo(t); FrameStats s = sg.sync(); { RenderingScope r(sg); render(); } }
/// ```
///
/// The classification is automatic (architecture.md): static geometry is merged into
/// world-space chunks; shapes below the same chain of dynamic transforms form one rigid
/// object per chain with one instance per path; deforming meshes get their own objects;
/// shared Separators and meshes (DEF/USE) become one object with several instances. Moving and
/// resting parts are reclassified with hysteresis. Whatever the classes, the hits after sync()
/// equal those of a scene built from scratch on the same graph state.
///
/// Threads: edits, advanceTo() and sync() run on one thread; queries of backendScene() may run
/// on many threads between syncs. While the rendering flag is set (setRendering, or a
/// RenderingScope) every edit of a node under the root, and advanceTo()/sync()/setRoot(),
/// throws tg::Error, so a frame never sees a half-done edit.
class SceneGraph : private NodeObserver {
 public:
  /// An empty graph with its own backend scene.
  explicit SceneGraph(const SyncOptions& options = {});
  ~SceneGraph() override;
  SceneGraph(const SceneGraph&) = delete;
  SceneGraph& operator=(const SceneGraph&) = delete;

  /// Sets the graph to sync (null clears it); the next sync() rebuilds everything.
  void setRoot(ref_ptr<Node> root);
  /// The root, or null.
  Node* root() const;

  /// The clock animators read.
  Clock& clock();
  /// The clock, read-only.
  const Clock& clock() const;
  /// Sets the clock to `time` and evaluates the animators that feed the graph (found through
  /// connected fields, plus those added with addAnimator) in dependency order, copying their
  /// outputs to the connected fields. The changes are seen by the next sync().
  void advanceTo(double time);
  /// Keeps an animator evaluated even when no connection into the graph leads to it.
  void addAnimator(ref_ptr<Animator> animator);
  /// Undoes addAnimator.
  void removeAnimator(const Animator* animator);

  /// Brings the backend scene up to date with the graph (visiting only what changed since
  /// the last sync), commits it, and returns the frame's statistics.
  FrameStats sync();
  /// Counters of the last sync.
  const SyncDebugStats& debugStats() const;
  /// Number of syncs so far.
  std::uint64_t frame() const;

  /// The backend scene (committed by sync()).
  Scene& backendScene();
  /// The backend scene, read-only.
  const Scene& backendScene() const;

  /// Maps a backend hit (instanceId, primId) to the mesh node, its triangle and the material
  /// and texture in effect; invalid HitInfo for misses and unknown instances.
  HitInfo hitInfo(const Hit& hit) const;
  /// The dynamics class of a backend instance (Static for unknown ids).
  DynamicsClass instanceClass(InstanceId instance) const;
  /// Backend instances held for the graph, ascending (for renderers filling per-instance
  /// material tables once per sync).
  std::vector<InstanceId> instanceIds() const;
  /// The segments of an instance in triangle order (empty for unknown ids). A shared object
  /// has the same segment boundaries in all its instances, but materials may differ per path.
  std::vector<MeshSegment> segments(InstanceId instance) const;
  /// Backend instances whose object holds `shape` (O(instances); for tests and tools).
  std::vector<InstanceId> instancesOf(const ShapeNode& shape) const;
  /// True when the classifier currently treats `node` (a transform or a mesh) as dynamic:
  /// driven by an animator or observed to change and not yet at rest.
  bool isDynamic(const Node& node) const;

  /// The lights found in the graph, on or off, in world space, in traversal order.
  std::vector<WorldLight> lights() const;
  /// The first camera in traversal order, in world space, or nothing.
  std::optional<WorldCamera> camera() const;

  /// Sets or clears the rendering flag. Whoever renders sets it for the duration of a frame;
  /// while set, edits of nodes under the root and advanceTo()/sync()/setRoot() throw.
  void setRendering(bool rendering);
  /// The rendering flag.
  bool rendering() const;

 private:
  void nodeChanged(const Notification& notification) override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Sets a SceneGraph's rendering flag for its lifetime (exception-safe).
class RenderingScope {
 public:
  /// Sets the flag until the scope ends.
  explicit RenderingScope(SceneGraph& graph) : graph_(graph) { graph_.setRendering(true); }
  ~RenderingScope() { graph_.setRendering(false); }
  RenderingScope(const RenderingScope&) = delete;
  RenderingScope& operator=(const RenderingScope&) = delete;

 private:
  SceneGraph& graph_;
};

}  // namespace tg
