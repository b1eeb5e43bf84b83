#include "tracegraph/scenegraph/SceneGraph.h"

#include <algorithm>
#include <unordered_set>

#include "AnimatorSchedule.h"
#include "RenderingRegistry.h"
#include "SyncEngine.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Field.h"
#include "tracegraph/scenegraph/Group.h"

namespace tg {

struct SceneGraph::Impl {
  explicit Impl(const SyncOptions& options) : scene(options.scene), engine(scene, options) {}

  Scene scene;  // declared before the engine, which refers to it
  sync::SyncEngine engine;
  Clock clock;
  ref_ptr<Node> root;
  bool rendering = false;
  std::vector<ref_ptr<Animator>> explicitAnimators;
  sync::AnimatorSchedule schedule;
  std::uint64_t scheduleGeneration = ~std::uint64_t(0);
  bool scheduleStale = true;

  void reject(const char* call) const {
    if (rendering)
      throw Error(std::string(call) +
                  " rejected: the scene graph is being rendered (edit between frames)");
  }

  /// Seeds of the animator schedule: nodes with connected fields known to the engine, nodes
  /// with connected fields in subtrees added since the last sync, and explicit animators.
  std::vector<const Node*> seeds() const {
    std::vector<const Node*> out;
    for (const auto& [node, count] : engine.connectedNodes()) out.push_back(node);
    std::vector<const Node*> stack = engine.pendingSubtrees();
    std::unordered_set<const Node*> seen;
    while (!stack.empty()) {
      const Node* n = stack.back();
      stack.pop_back();
      if (!seen.insert(n).second) continue;
      if (n->hasConnectedField()) out.push_back(n);
      if (const auto* g = dynamic_cast<const Group*>(n))
        for (const ref_ptr<Node>& c : g->children()) stack.push_back(c.get());
    }
    for (const ref_ptr<Animator>& a : explicitAnimators) out.push_back(a.get());
    return out;
  }
};

SceneGraph::SceneGraph(const SyncOptions& options) : impl_(std::make_unique<Impl>(options)) {}

SceneGraph::~SceneGraph() {
  if (impl_->rendering) detail::endRendering(impl_->root.get());
  if (impl_->root) impl_->root->removeObserver(this);
}

void SceneGraph::setRoot(ref_ptr<Node> root) {
  impl_->reject("SceneGraph::setRoot");
  if (impl_->root) impl_->root->removeObserver(this);
  impl_->root = std::move(root);
  if (impl_->root) impl_->root->addObserver(this);
  impl_->engine.setRoot(impl_->root.get());
  impl_->scheduleStale = true;
}

Node* SceneGraph::root() const {
  return impl_->root.get();
}

Clock& SceneGraph::clock() {
  return impl_->clock;
}
const Clock& SceneGraph::clock() const {
  return impl_->clock;
}

void SceneGraph::advanceTo(double time) {
  impl_->reject("SceneGraph::advanceTo");
  impl_->clock.setTime(time);
  const std::uint64_t generation = Field::connectionGeneration();
  if (impl_->scheduleStale || generation != impl_->scheduleGeneration ||
      !impl_->engine.pendingSubtrees().empty()) {
    impl_->schedule.rebuild(impl_->seeds());
    impl_->scheduleGeneration = generation;
    impl_->scheduleStale = false;
  }
  impl_->schedule.evaluate(time);
}

void SceneGraph::addAnimator(ref_ptr<Animator> animator) {
  if (!animator) throw Error("SceneGraph::addAnimator: null animator");
  impl_->explicitAnimators.push_back(std::move(animator));
  impl_->scheduleStale = true;
}

void SceneGraph::removeAnimator(const Animator* animator) {
  auto& v = impl_->explicitAnimators;
  v.erase(std::remove_if(v.begin(), v.end(),
                         [animator](const ref_ptr<Animator>& a) { return a.get() == animator; }),
          v.end());
  impl_->scheduleStale = true;
}

FrameStats SceneGraph::sync() {
  impl_->reject("SceneGraph::sync");
  // Connections seen by this sync may change which animators feed the graph.
  if (!impl_->engine.pendingSubtrees().empty()) impl_->scheduleStale = true;
  return impl_->engine.sync(impl_->clock.time());
}

const SyncDebugStats& SceneGraph::debugStats() const {
  return impl_->engine.debug();
}

std::uint64_t SceneGraph::frame() const {
  return impl_->engine.frame();
}

Scene& SceneGraph::backendScene() {
  return impl_->scene;
}
const Scene& SceneGraph::backendScene() const {
  return impl_->scene;
}

HitInfo SceneGraph::hitInfo(const Hit& hit) const {
  HitInfo info;
  if (!hit.valid()) return info;
  const sync::Segment* s = impl_->engine.instances().segment(hit.instanceId, hit.primId);
  if (!s) return info;
  info.shape = s->shape;
  info.triangle = hit.primId - s->primBegin;
  info.material = s->material;
  info.texture = s->texture;
  info.dynamics = impl_->engine.instances().find(hit.instanceId)->cls;
  return info;
}

DynamicsClass SceneGraph::instanceClass(InstanceId instance) const {
  const sync::InstanceInfo* info = impl_->engine.instances().find(instance);
  return info ? info->cls : DynamicsClass::Static;
}

std::vector<InstanceId> SceneGraph::instanceIds() const {
  std::vector<InstanceId> out;
  out.reserve(impl_->engine.instances().size());
  for (const auto& [id, info] : impl_->engine.instances().all()) out.push_back(id);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<MeshSegment> SceneGraph::segments(InstanceId instance) const {
  std::vector<MeshSegment> out;
  const sync::InstanceInfo* info = impl_->engine.instances().find(instance);
  if (!info) return out;
  out.reserve(info->segments.size());
  for (std::size_t i = 0; i < info->segments.size(); ++i) {
    const sync::Segment& s = info->segments[i];
    const std::uint32_t end = i + 1 < info->segments.size()
                                  ? info->segments[i + 1].primBegin
                                  : static_cast<std::uint32_t>(info->triangles);
    out.push_back({s.primBegin, end, s.shape, s.material, s.texture});
  }
  return out;
}

std::vector<InstanceId> SceneGraph::instancesOf(const ShapeNode& shape) const {
  std::vector<InstanceId> out;
  for (const auto& [id, info] : impl_->engine.instances().all())
    for (const sync::Segment& s : info.segments)
      if (s.shape == &shape) {
        out.push_back(id);
        break;
      }
  std::sort(out.begin(), out.end());
  return out;
}

bool SceneGraph::isDynamic(const Node& node) const {
  return impl_->engine.classifier().isDynamic(node);
}

std::vector<WorldLight> SceneGraph::lights() const {
  return impl_->engine.lights();
}

std::optional<WorldCamera> SceneGraph::camera() const {
  return impl_->engine.camera();
}

void SceneGraph::setRendering(bool rendering) {
  if (rendering == impl_->rendering) return;
  impl_->rendering = rendering;
  if (rendering)
    detail::beginRendering(impl_->root.get());
  else
    detail::endRendering(impl_->root.get());
}

bool SceneGraph::rendering() const {
  return impl_->rendering;
}

void SceneGraph::nodeChanged(const Notification& notification) {
  impl_->engine.noteChange(notification);
}

}  // namespace tg
