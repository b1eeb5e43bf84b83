/// @file ObjectCache.h
/// Backend objects keyed by their content, shared by every frame with the same content
/// (internal). This is what turns DEF/USE sharing into one object with several instances,
/// and what lets a region walked again find its unchanged objects instead of rebuilding them.
#pragma once

#include <memory>
#include <unordered_map>
#include <vector>

#include "MeshBaker.h"
#include "tracegraph/backend/Scene.h"

namespace tg::sync {

/// Usage plus the ordered content of an object.
struct ContentKey {
  ObjectUsage usage = ObjectUsage::Static;
  std::vector<ContentItem> items;
  bool operator==(const ContentKey&) const = default;
};

/// Hash of a ContentKey (addresses, versions and matrix bits).
struct ContentKeyHash {
  std::size_t operator()(const ContentKey& k) const;
};

/// One backend object and what it was built from.
struct ObjectEntry {
  ContentKey key;
  ObjectId id = kInvalidId;
  std::size_t refs = 0;  ///< frames using the object
  std::size_t triangles = 0;
  std::vector<std::uint32_t> primBegin;  ///< first triangle of each item
  std::uint64_t builtVersion = 0;        ///< deforming: shape version of the backend mesh
};

/// Objects by content; releases unused ones at the end of a sync.
class ObjectCache {
 public:
  explicit ObjectCache(Scene& scene) : scene_(scene) {}
  /// The object for `key` (built now when new), with one more user. Deforming objects found
  /// in the cache are brought to their mesh's current version.
  ObjectEntry* acquire(const ContentKey& key);
  /// One user less; the object is destroyed by collect() if nobody takes it again.
  void release(ObjectEntry* entry);
  /// The deforming object of `shape`, or null.
  ObjectEntry* deforming(const ShapeNode* shape) const;
  /// Gives a deforming object its mesh's current points; true when it had to be updated.
  bool refresh(ObjectEntry& entry);
  /// Destroys objects nobody uses; returns how many.
  std::size_t collect();
  /// Objects created since the last call.
  std::size_t takeCreatedCount();

 private:
  Scene& scene_;
  std::unordered_map<ContentKey, std::unique_ptr<ObjectEntry>, ContentKeyHash> entries_;
  std::unordered_map<const ShapeNode*, ObjectEntry*> deforming_;
  std::vector<ObjectEntry*> unused_;
  std::size_t created_ = 0;
};

}  // namespace tg::sync
