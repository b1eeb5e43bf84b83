/// @file InstanceTable.h
/// What each backend instance holds in graph terms (internal): the map from a hit's
/// (instanceId, primId) back to the mesh node, its triangle and its material.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "tracegraph/backend/Scene.h"
#include "tracegraph/scenegraph/DynamicsClass.h"
#include "tracegraph/scenegraph/FrameStats.h"
#include "tracegraph/scenegraph/MaterialNode.h"
#include "tracegraph/scenegraph/ShapeNode.h"
#include "tracegraph/scenegraph/TextureNode.h"

namespace tg::sync {

/// A run of an object's triangles that come from one shape occurrence.
struct Segment {
  std::uint32_t primBegin = 0;
  const ShapeNode* shape = nullptr;
  const MaterialNode* material = nullptr;
  const TextureNode* texture = nullptr;
};

/// One instance: its class, its triangle count and its segments in primBegin order.
struct InstanceInfo {
  DynamicsClass cls = DynamicsClass::Static;
  std::size_t triangles = 0;
  std::vector<Segment> segments;
};

/// Instance infos by backend id, with running triangle totals per class.
class InstanceTable {
 public:
  /// Adds or replaces the info of `id`.
  void set(InstanceId id, InstanceInfo info);
  /// Forgets `id`.
  void erase(InstanceId id);
  /// The info of `id`, or null.
  const InstanceInfo* find(InstanceId id) const;
  /// The segment holding triangle `primId` of instance `id`, or null.
  const Segment* segment(InstanceId id, std::uint32_t primId) const;
  /// Triangles per class over all instances.
  const TriangleCounts& totals() const { return totals_; }
  /// Number of instances.
  std::size_t size() const { return infos_.size(); }
  /// All infos (for scans in tests and tools).
  const std::unordered_map<InstanceId, InstanceInfo>& all() const { return infos_; }

 private:
  void count(const InstanceInfo& info, bool add);

  std::unordered_map<InstanceId, InstanceInfo> infos_;
  TriangleCounts totals_;
};

}  // namespace tg::sync
