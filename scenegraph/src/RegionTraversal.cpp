// Walking a region of the graph and undoing what an earlier walk produced.
#include <cmath>
#include <iterator>
#include <limits>

#include "MeshBaker.h"
#include "SyncEngine.h"
#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/NodeVisitor.h"

namespace tg::sync {

Affine3d chainMatrix(const Chain& chain) {
  Affine3d m;
  for (const TransformNode* t : chain) m = m * t->localMatrix();
  return m;
}

/// Walks one region with Open Inventor state rules: transforms and materials accumulate in
/// traversal order, a Separator saves and restores them (and opens a nested region).
class RegionBuilder final : public NodeVisitor {
 public:
  RegionBuilder(SyncEngine& engine, Region& region)
      : e_(engine), region_(region), state_(region.entry) {}

  void visitNode(Node& node) {
    ++e_.debug_.nodesVisited;
    region_.visited.emplace_back(&node);
    RegionList& list = e_.visitedIn_[&node];
    list.push_back(&region_);
    region_.visitedLinks.emplace_back(&node, std::prev(list.end()));
    if (node.hasConnectedField()) {
      region_.connected.push_back(&node);
      ++e_.connected_[&node];
    }
    node.accept(*this);
  }

  void visitChildren(Group& group) {
    for (std::size_t i = 0; i < group.numChildren(); ++i) {
      if (!group.isChildActive(i)) continue;
      state_.path.push_back(static_cast<std::uint32_t>(i));
      visitNode(*group.child(i));
      state_.path.pop_back();
    }
  }

  using NodeVisitor::apply;

  void apply(Group& group) override {
    if (!group.isolatesState()) {
      visitChildren(group);  // state changes below leak to the following siblings
      return;
    }
    auto child = std::make_unique<Region>();
    child->node = &group;
    child->parent = &region_;
    child->entry = state_;
    // A Separator reached along several paths is a DEF/USE share: its content becomes one
    // object in the Separator's frame, with one instance per path.
    if (group.parents().size() > 1 && &group != e_.root_.get()) {
      const DynamicsClass cls = state_.inDynamic ? DynamicsClass::Rigid : DynamicsClass::Static;
      child->entry.frame = e_.beginFrame(region_, state_, cls, usageOf(cls));
      child->entry.bake = Affine3d{};
    }
    RegionList& opened = e_.opened_[&group];
    opened.push_back(child.get());
    child->openedLink = std::prev(opened.end());
    Region& c = *child;
    region_.children.push_back(std::move(child));
    e_.walk(c);
  }

  void apply(TransformNode& transform) override {
    state_.chain.push_back(&transform);
    if (e_.classifier_.isDynamic(transform)) {
      // Everything after a dynamic transform lives in its frame: one rigid object per chain
      // of dynamic transforms, with later static transforms baked into its vertices.
      state_.inDynamic = true;
      state_.frame = e_.beginFrame(region_, state_, DynamicsClass::Rigid, ObjectUsage::Rigid);
      state_.bake = Affine3d{};
    } else {
      state_.bake = state_.bake * transform.localMatrix();
    }
  }

  void apply(ShapeNode& shape) override {
    if (!e_.shapeValid(shape)) {
      ++e_.debug_.invalidShapes;
      return;
    }
    if (shape.triangleCount() == 0) return;
    if (!bakesIntoFloatRange(shape, state_.bake)) {
      // Finite matrices whose product throws the points beyond float range: nothing that can
      // be hit; skipping the shape keeps its chunk or object usable for the rest.
      ++e_.debug_.invalidShapes;
      return;
    }
    ShapeOcc occ{&shape, state_.material, state_.texture, state_.bake, shape.geometryVersion()};
    if (e_.classifier_.isDynamic(shape)) {
      // Deforming meshes keep their own points; the whole chain becomes the instance matrix.
      occ.bake = Affine3d{};
      FrameOcc* f =
          e_.beginFrame(region_, state_, DynamicsClass::Deforming, ObjectUsage::Deforming);
      e_.addToFrame(region_, f, state_.path, occ);
    } else if (shape.parents().size() > 1) {
      occ.bake = Affine3d{};
      const DynamicsClass cls = state_.inDynamic ? DynamicsClass::Rigid : DynamicsClass::Static;
      e_.addToFrame(region_, e_.beginFrame(region_, state_, cls, usageOf(cls)), state_.path, occ);
    } else if (state_.frame) {
      e_.addToFrame(region_, state_.frame, state_.path, occ);
    } else {
      e_.chunks_.add(state_.path, occ);
      region_.staticShapes.push_back(state_.path);
    }
  }

  void apply(MaterialNode& material) override { state_.material = &material; }
  void apply(TextureNode& texture) override { state_.texture = &texture; }

  void apply(LightNode& light) override {
    auto o = std::make_unique<PlacedOcc<LightNode>>(
        PlacedOcc<LightNode>{&light, state_.chain, state_.path});
    e_.lights_[state_.path] = o.get();
    region_.lights.push_back(std::move(o));
  }

  void apply(CameraNode& camera) override {
    auto o = std::make_unique<PlacedOcc<CameraNode>>(
        PlacedOcc<CameraNode>{&camera, state_.chain, state_.path});
    e_.cameras_[state_.path] = o.get();
    region_.cameras.push_back(std::move(o));
  }

 private:
  static bool bakesIntoFloatRange(const ShapeNode& shape, const Affine3d& bake) {
    if (bake == Affine3d::identity()) return true;
    const Box3d b = bakedBounds(shape, bake);
    const double limit = static_cast<double>(std::numeric_limits<float>::max());
    for (std::size_t a = 0; a < 3; ++a)
      if (!(std::abs(b.lower[a]) < limit && std::abs(b.upper[a]) < limit)) return false;
    return true;
  }

  static ObjectUsage usageOf(DynamicsClass cls) {
    return cls == DynamicsClass::Rigid ? ObjectUsage::Rigid : ObjectUsage::Static;
  }

  SyncEngine& e_;
  Region& region_;
  EntryState state_;
};

void SyncEngine::walk(Region& region) {
  RegionBuilder builder(*this, region);
  if (region.isRoot) {
    if (root_) builder.visitNode(*root_);
  } else {
    builder.visitChildren(static_cast<Group&>(*region.node));
  }
}

void SyncEngine::clear(Region& region) {
  for (std::unique_ptr<Region>& child : region.children) {
    clear(*child);
    auto it = opened_.find(child->node);
    if (it != opened_.end()) {
      it->second.erase(child->openedLink);
      if (it->second.empty()) opened_.erase(it);
    }
    deadRegions_.push_back(std::move(child));
  }
  region.children.clear();
  for (const auto& [frame, path] : region.frameShapes) {
    if (frame->dead) continue;
    frame->shapes.erase(path);
    queueFrame(frame);
  }
  region.frameShapes.clear();
  for (const Path& path : region.staticShapes) chunks_.remove(path);
  region.staticShapes.clear();
  for (std::unique_ptr<FrameOcc>& frame : region.frames) {
    killFrame(*frame);
    deadFrames_.push_back(std::move(frame));
  }
  region.frames.clear();
  for (const auto& o : region.lights) {
    auto it = lights_.find(o->path);
    if (it != lights_.end() && it->second == o.get()) lights_.erase(it);
  }
  region.lights.clear();
  for (const auto& o : region.cameras) {
    auto it = cameras_.find(o->path);
    if (it != cameras_.end() && it->second == o.get()) cameras_.erase(it);
  }
  region.cameras.clear();
  for (const auto& [node, link] : region.visitedLinks) {
    auto it = visitedIn_.find(node);
    it->second.erase(link);
    if (it->second.empty()) visitedIn_.erase(it);
  }
  region.visitedLinks.clear();
  for (const Node* node : region.connected) {
    auto it = connected_.find(node);
    if (it != connected_.end() && --it->second == 0) connected_.erase(it);
  }
  region.connected.clear();
  for (ref_ptr<Node>& node : region.visited) leftNodes_.push_back(std::move(node));
  region.visited.clear();
}

FrameOcc* SyncEngine::beginFrame(Region& region, const EntryState& state, DynamicsClass cls,
                                 ObjectUsage usage) {
  auto frame = std::make_unique<FrameOcc>();
  frame->cls = cls;
  frame->usage = usage;
  frame->chain = state.chain;
  frame->owner = &region;
  // Index the frame under every dynamic transform of its chain: a change of one of them
  // recomputes exactly these instance matrices and nothing else.
  for (const TransformNode* t : frame->chain) {
    if (!classifier_.isDynamic(*t)) continue;
    std::list<FrameOcc*>& list = framesOf_[t];
    list.push_back(frame.get());
    frame->chainLinks.emplace_back(t, std::prev(list.end()));
  }
  FrameOcc* f = frame.get();
  queueFrame(f);
  region.frames.push_back(std::move(frame));
  return f;
}

void SyncEngine::addToFrame(Region& region, FrameOcc* frame, const Path& path,
                            const ShapeOcc& shape) {
  frame->shapes[path] = shape;
  region.frameShapes.emplace_back(frame, path);
  queueFrame(frame);
}

void SyncEngine::killFrame(FrameOcc& frame) {
  frame.dead = true;
  for (const auto& [t, link] : frame.chainLinks) {
    auto it = framesOf_.find(t);
    it->second.erase(link);
    if (it->second.empty()) framesOf_.erase(it);
  }
  frame.chainLinks.clear();
  dropInstance(frame.instance);
  if (frame.object) cache_.release(frame.object);
  frame.object = nullptr;
}

void SyncEngine::queueFrame(FrameOcc* frame) {
  if (frame->queued) return;
  frame->queued = true;
  queuedFrames_.push_back(frame);
}

void SyncEngine::queueMatrix(FrameOcc* frame) {
  if (frame->matrixQueued) return;
  frame->matrixQueued = true;
  queuedMatrices_.push_back(frame);
}

bool SyncEngine::shapeValid(const ShapeNode& shape) {
  Validity& v = validity_[&shape];
  const std::uint64_t version = shape.geometryVersion();
  if (v.version != version || version == 0) {
    v.version = version;
    v.valid = shape.validate().empty();
  }
  return v.valid;
}

}  // namespace tg::sync
