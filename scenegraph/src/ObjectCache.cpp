#include "ObjectCache.h"

#include <algorithm>
#include <bit>
#include <utility>

namespace tg::sync {
namespace {

void mix(std::size_t& h, std::uint64_t v) {
  h ^= std::hash<std::uint64_t>()(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
}

}  // namespace

std::size_t ContentKeyHash::operator()(const ContentKey& k) const {
  std::size_t h = static_cast<std::size_t>(k.usage);
  for (const ContentItem& item : k.items) {
    mix(h, reinterpret_cast<std::uintptr_t>(item.shape));
    mix(h, item.version);
    for (const auto& row : item.bake.m)
      for (double v : row) mix(h, std::bit_cast<std::uint64_t>(v));
  }
  return h;
}

ObjectEntry* ObjectCache::acquire(const ContentKey& key) {
  auto it = entries_.find(key);
  if (it != entries_.end()) {
    ObjectEntry* e = it->second.get();
    ++e->refs;
    if (key.usage == ObjectUsage::Deforming) refresh(*e);
    return e;
  }
  auto entry = std::make_unique<ObjectEntry>();
  entry->key = key;
  TriangleMesh mesh = bakeMesh(key.items, entry->primBegin);
  // Shapes are validated before they get here, but a huge matrix can still overflow baked
  // points to infinity. Such geometry cannot be hit anyway; an empty object (which gets no
  // instance) keeps the sync from failing half-way.
  if (!mesh.validate().empty()) mesh = TriangleMesh{};
  entry->triangles = mesh.triangleCount();
  entry->id = scene_.createObject(std::move(mesh), key.usage);
  entry->refs = 1;
  ++created_;
  ObjectEntry* e = entry.get();
  if (key.usage == ObjectUsage::Deforming) {
    e->builtVersion = key.items.front().shape->geometryVersion();
    deforming_[key.items.front().shape] = e;
  }
  entries_.emplace(key, std::move(entry));
  return e;
}

void ObjectCache::release(ObjectEntry* entry) {
  if (--entry->refs == 0) unused_.push_back(entry);
}

ObjectEntry* ObjectCache::deforming(const ShapeNode* shape) const {
  auto it = deforming_.find(shape);
  return it == deforming_.end() ? nullptr : it->second;
}

bool ObjectCache::refresh(ObjectEntry& entry) {
  const ShapeNode* shape = entry.key.items.front().shape;
  const std::uint64_t version = shape->geometryVersion();
  if (version == entry.builtVersion) return false;
  const ShapeGeometry g = shape->geometry();
  const TriangleMesh& current = scene_.objectMesh(entry.id);
  // Points only: the backend keeps indices and attributes and rebuilds from new positions.
  if (g.points.size() == current.positions.size() && g.normals.empty() && g.uvs.empty() &&
      current.normals.empty() && current.uvs.empty() &&
      g.indices.size() == current.indices.size() &&
      std::equal(
          g.indices.begin(), g.indices.end(), current.indices.begin(),
          [](std::int32_t a, std::uint32_t b) { return static_cast<std::uint32_t>(a) == b; })) {
    scene_.setObjectPositions(entry.id, g.points);
  } else {
    TriangleMesh mesh = bakeMesh(entry.key.items, entry.primBegin);
    entry.triangles = mesh.triangleCount();
    scene_.setObjectMesh(entry.id, std::move(mesh));
  }
  entry.builtVersion = version;
  return true;
}

std::size_t ObjectCache::collect() {
  std::size_t destroyed = 0;
  // An entry released, taken again and released again is listed twice: dedupe first, since
  // collecting it frees it.
  std::sort(unused_.begin(), unused_.end());
  unused_.erase(std::unique(unused_.begin(), unused_.end()), unused_.end());
  for (ObjectEntry* e : unused_) {
    if (e->refs != 0) continue;
    auto it = entries_.find(e->key);
    scene_.destroyObject(e->id);
    if (e->key.usage == ObjectUsage::Deforming) {
      auto d = deforming_.find(e->key.items.front().shape);
      if (d != deforming_.end() && d->second == e) deforming_.erase(d);
    }
    entries_.erase(it);
    ++destroyed;
  }
  unused_.clear();
  return destroyed;
}

std::size_t ObjectCache::takeCreatedCount() {
  return std::exchange(created_, 0);
}

}  // namespace tg::sync
