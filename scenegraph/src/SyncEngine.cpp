#include "SyncEngine.h"

#include <chrono>
#include <unordered_set>

#include "tracegraph/scenegraph/Group.h"

namespace tg::sync {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

ContentKey keyOf(ObjectUsage usage, const std::map<Path, ShapeOcc>& shapes) {
  ContentKey key;
  key.usage = usage;
  key.items.reserve(shapes.size());
  for (const auto& [path, s] : shapes)
    // Deforming objects follow their mesh's points, so the version is not part of their key.
    key.items.push_back({s.shape, usage == ObjectUsage::Deforming ? 0 : s.version, s.bake});
  return key;
}

InstanceInfo infoOf(DynamicsClass cls, const std::map<Path, ShapeOcc>& shapes,
                    const ObjectEntry& entry) {
  InstanceInfo info;
  info.cls = cls;
  info.triangles = entry.triangles;
  info.segments.reserve(shapes.size());
  std::size_t i = 0;
  for (const auto& [path, s] : shapes)
    info.segments.push_back({entry.primBegin[i++], s.shape, s.material, s.texture});
  return info;
}

}  // namespace

SyncEngine::SyncEngine(Scene& scene, const SyncOptions& options)
    : scene_(scene),
      options_(options),
      classifier_(options),
      cache_(scene),
      chunks_(options.staticChunkGrid) {}

SyncEngine::~SyncEngine() = default;

void SyncEngine::setRoot(Node* root) {
  root_ = ref_ptr<Node>(root);
  rootDirty_ = true;
  dirty_.clear();
  structureChildren_.clear();
}

void SyncEngine::noteChange(const Notification& n) {
  Dirty& d = dirty_[n.source];
  if (!d.node) d.node = ref_ptr<Node>(n.source);
  d.kinds |= n.kind;
  if (n.child && hasAny(n.kind, ChangeKind::Structure))
    structureChildren_.emplace_back(const_cast<Node*>(n.child));
}

std::vector<const Node*> SyncEngine::pendingSubtrees() const {
  std::vector<const Node*> out;
  if (rootDirty_) {
    if (root_) out.push_back(root_.get());
    return out;
  }
  for (const ref_ptr<Node>& c : structureChildren_) out.push_back(c.get());
  for (const auto& [node, d] : dirty_)
    if (hasAny(d.kinds, ChangeKind::Connection)) out.push_back(node);
  return out;
}

void SyncEngine::collectRegions(const Node* node, bool opened, std::vector<Region*>& out) const {
  if (opened) {
    auto it = opened_.find(node);
    if (it != opened_.end()) {
      out.insert(out.end(), it->second.begin(), it->second.end());
      return;
    }
  }
  auto it = visitedIn_.find(node);
  if (it != visitedIn_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
}

FrameStats SyncEngine::sync(double time) {
  const auto start = Clock::now();
  debug_ = {};
  ++frame_;
  FrameStats stats;
  stats.frame = frame_;
  stats.time = time;

  if (rootDirty_) {
    if (rootRegion_) {
      clear(*rootRegion_);
      deadRegions_.push_back(std::move(rootRegion_));
    }
    for (auto& [node, d] : dirty_) leftNodes_.push_back(std::move(d.node));
    dirty_.clear();
    structureChildren_.clear();
    rootDirty_ = false;
    if (root_) {
      rootRegion_ = std::make_unique<Region>();
      rootRegion_->isRoot = true;
      rootRegion_->node = root_.get();
      walk(*rootRegion_);
      ++debug_.regionsRetraversed;
    }
  } else {
    // (1) Sort the changes into cheap updates and regions to walk again.
    std::vector<Region*> regions;
    std::vector<const TransformNode*> moved;
    std::vector<const ShapeNode*> deformed;
    debug_.dirtyNodes = dirty_.size();
    for (auto& [key, d] : dirty_) {
      ++debug_.nodesVisited;
      Node& n = *d.node;
      const bool inGraph = visitedIn_.count(&n) != 0;
      if (hasAny(d.kinds, ChangeKind::Structure | ChangeKind::Visibility))
        collectRegions(&n, true, regions);
      if (hasAny(d.kinds, ChangeKind::Connection)) collectRegions(&n, false, regions);
      // Nodes not yet in the graph are being set up (a subtree added this frame): their
      // edits are not movement, and the walk of their new region sees their current state.
      if (const auto* t = dynamic_cast<const TransformNode*>(&n);
          t && inGraph && hasAny(d.kinds, ChangeKind::Transform)) {
        if (classifier_.noteChange(n, frame_)) {
          // A static transform started moving: its region is walked again so that what
          // follows it leaves the static chunks for a rigid object.
          ++debug_.promoted;
          collectRegions(&n, false, regions);
        } else {
          moved.push_back(t);
        }
      }
      if (const auto* s = dynamic_cast<const ShapeNode*>(&n);
          s && inGraph && hasAny(d.kinds, ChangeKind::Points | ChangeKind::Topology)) {
        if (classifier_.noteChange(n, frame_)) {
          ++debug_.promoted;
          collectRegions(&n, false, regions);
        } else {
          // Already deforming: new points for its object, unless the mesh became invalid or
          // its triangle count changed, which changes what its region produces.
          const ObjectEntry* e = cache_.deforming(s);
          if (e && shapeValid(*s) && s->triangleCount() == e->triangles)
            deformed.push_back(s);
          else
            collectRegions(&n, false, regions);
        }
      }
    }
    // A child that gained or lost its second parent changes from inline to shared or back
    // in every region that visits it.
    for (const ref_ptr<Node>& c : structureChildren_)
      if (c->parents().size() <= 2) collectRegions(c.get(), false, regions);
    for (const ref_ptr<Node>& n : classifier_.takeDemotions(frame_)) {
      if (!visitedIn_.count(n.get())) continue;
      ++debug_.demoted;
      collectRegions(n.get(), false, regions);
    }
    for (auto& [node, d] : dirty_) leftNodes_.push_back(std::move(d.node));
    dirty_.clear();
    structureChildren_.clear();

    // (2) Walk each affected region once: the outermost ones only, since walking a region
    // walks everything nested in it.
    const auto walkStart = Clock::now();
    const std::unordered_set<Region*> marked(regions.begin(), regions.end());
    std::unordered_set<Region*> done;
    for (Region* r : regions) {
      if (!done.insert(r).second) continue;
      bool covered = false;
      for (Region* p = r->parent; p && !covered; p = p->parent) covered = marked.count(p) != 0;
      if (covered) continue;
      clear(*r);
      walk(*r);
      ++debug_.regionsRetraversed;
    }

    // (3) Cheap updates: matrices of the frames below moved transforms, deforming points.
    for (const TransformNode* t : moved) {
      auto it = framesOf_.find(t);
      if (it == framesOf_.end()) continue;
      for (FrameOcc* f : it->second) queueMatrix(f);
    }
    for (const ShapeNode* s : deformed)
      if (ObjectEntry* e = cache_.deforming(s); e && cache_.refresh(*e)) ++debug_.deformingUpdated;
    if (debug_.promoted + debug_.demoted > 0) debug_.reclassifyMs = msSince(walkStart);
  }

  // (4) Objects and instances of changed frames and chunks.
  for (FrameOcc* f : queuedFrames_) {
    f->queued = false;
    if (!f->dead) finishFrame(*f);
  }
  queuedFrames_.clear();
  for (FrameOcc* f : queuedMatrices_) {
    f->matrixQueued = false;
    if (!f->dead) finishMatrix(*f);
  }
  queuedMatrices_.clear();
  for (Chunk* c : chunks_.takeDirty()) finishChunk(*c);
  chunks_.dropEmpty();
  debug_.objectsDestroyed = cache_.collect();
  debug_.objectsCreated = cache_.takeCreatedCount();

  const CommitStats commit = scene_.commit();

  // Forget nodes that left the graph, then let them go.
  for (const ref_ptr<Node>& n : leftNodes_) {
    if (visitedIn_.count(n.get())) continue;
    classifier_.forget(n.get());
    if (const auto* s = dynamic_cast<const ShapeNode*>(n.get())) validity_.erase(s);
  }
  leftNodes_.clear();
  deadFrames_.clear();
  deadRegions_.clear();

  stats.triangles = instances_.totals();
  stats.instances = instances_.size();
  stats.objectsRebuilt = commit.objectsRebuilt;
  stats.objectsRefitted = commit.objectsRefitted;
  stats.trianglesRebuilt = commit.trianglesRebuilt;
  stats.reclassified = debug_.promoted + debug_.demoted;
  stats.rebuildMs = commit.rebuildMs;
  stats.toplevelMs = commit.topLevelMs;
  stats.syncMs = msSince(start);
  return stats;
}

void SyncEngine::setInstance(InstanceId& instance, ObjectEntry* entry, const Affine3d& matrix,
                             bool objectChanged, InstanceInfo info) {
  // A singular matrix (zero scale) flattens the geometry to nothing that can be hit, exactly
  // as baking it would; the backend rejects such instances, so the frame simply has none.
  const bool usable = entry->triangles > 0 && matrix.isFinite() && !matrix.isSingular();
  if (!usable || objectChanged) dropInstance(instance);
  if (!usable) return;
  if (instance == kInvalidId) {
    instance = scene_.createInstance(entry->id, matrix);
    ++debug_.instancesCreated;
  } else if (!(scene_.instanceTransform(instance) == matrix)) {
    scene_.setInstanceTransform(instance, matrix);
  }
  instances_.set(instance, std::move(info));
}

void SyncEngine::dropInstance(InstanceId& instance) {
  if (instance == kInvalidId) return;
  scene_.destroyInstance(instance);
  instances_.erase(instance);
  ++debug_.instancesDestroyed;
  instance = kInvalidId;
}

void SyncEngine::finishFrame(FrameOcc& f) {
  if (f.shapes.empty()) {
    dropInstance(f.instance);
    if (f.object) cache_.release(f.object);
    f.object = nullptr;
    return;
  }
  const ContentKey key = keyOf(f.usage, f.shapes);
  bool changed = false;
  if (!f.object || !(f.object->key == key)) {
    ObjectEntry* e = cache_.acquire(key);
    if (f.object) cache_.release(f.object);
    f.object = e;
    changed = true;
  }
  f.matrix = chainMatrix(f.chain);
  setInstance(f.instance, f.object, f.matrix, changed, infoOf(f.cls, f.shapes, *f.object));
}

void SyncEngine::finishMatrix(FrameOcc& f) {
  if (!f.object) return;
  ++debug_.framesUpdated;
  const Affine3d m = chainMatrix(f.chain);
  if (f.instance != kInvalidId && m == f.matrix) return;
  f.matrix = m;
  if (f.instance != kInvalidId && m.isFinite() && !m.isSingular()) {
    scene_.setInstanceTransform(f.instance, m);
    return;
  }
  setInstance(f.instance, f.object, m, false, infoOf(f.cls, f.shapes, *f.object));
}

void SyncEngine::finishChunk(Chunk& c) {
  if (c.shapes.empty()) {
    dropInstance(c.instance);
    if (c.object) cache_.release(c.object);
    c.object = nullptr;
    return;
  }
  const ContentKey key = keyOf(ObjectUsage::Static, c.shapes);
  bool changed = false;
  if (!c.object || !(c.object->key == key)) {
    ObjectEntry* e = cache_.acquire(key);
    if (c.object) cache_.release(c.object);
    c.object = e;
    changed = true;
    ++debug_.chunksRebuilt;
  }
  setInstance(c.instance, c.object, Affine3d{}, changed,
              infoOf(DynamicsClass::Static, c.shapes, *c.object));
}

std::vector<WorldLight> SyncEngine::lights() const {
  std::vector<WorldLight> out;
  out.reserve(lights_.size());
  for (const auto& [path, o] : lights_) {
    WorldLight w;
    w.node = o->node;
    w.data = o->node->lightData();
    const Affine3d m = chainMatrix(o->chain);
    w.data.position = Vec3f(m.transformPoint(Vec3d(w.data.position)));
    const Vec3d d = m.transformVector(Vec3d(w.data.direction));
    const double len = length(d);
    w.data.direction = len > 0.0 ? Vec3f(d / len) : Vec3f(0.0f, 0.0f, -1.0f);
    out.push_back(w);
  }
  return out;
}

std::optional<WorldCamera> SyncEngine::camera() const {
  if (cameras_.empty()) return std::nullopt;
  const PlacedOcc<CameraNode>& o = *cameras_.begin()->second;
  const CameraData c = o.node->cameraData();
  const Affine3d m = chainMatrix(o.chain);
  const Quaternion q = toQuaternion(c.orientation);
  Vec3d dir = m.transformVector(rotate(q, Vec3d(0.0, 0.0, -1.0)));
  Vec3d up = m.transformVector(rotate(q, Vec3d(0.0, 1.0, 0.0)));
  WorldCamera w;
  w.node = o.node;
  w.position = Vec3f(m.transformPoint(Vec3d(c.position)));
  const double dl = length(dir);
  if (dl > 0.0) dir = dir / dl;
  // Re-orthogonalise: a non-uniform scale above the camera may shear its frame.
  up = up - dir * dot(up, dir);
  const double ul = length(up);
  w.direction = dl > 0.0 ? Vec3f(dir) : Vec3f(0.0f, 0.0f, -1.0f);
  w.up = ul > 0.0 ? Vec3f(up / ul) : Vec3f(0.0f, 1.0f, 0.0f);
  w.fov = c.fov;
  w.hither = c.hither;
  w.aspect = c.aspect;
  return w;
}

}  // namespace tg::sync
