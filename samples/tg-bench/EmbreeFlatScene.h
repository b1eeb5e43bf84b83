/// @file EmbreeFlatScene.h
/// The flat peer of the sync suite: a synced Tracegraph scene copied instance by instance,
/// transformed to world space, into one Embree triangle geometry that is rebuilt from scratch
/// every frame. This is what a renderer without a two-level structure pays per frame of an
/// animation, and the baseline the two-level design has to beat. Only compiled when CMake found
/// Embree (TG_HAVE_EMBREE); the interface is free of Embree types, like EmbreePeer.h.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "tracegraph/backend/Scene.h"

namespace tg::bench {

/// One Embree scene at RTC_BUILD_QUALITY_LOW holding one triangle geometry.
class EmbreeFlatScene {
 public:
  /// Creates its own Embree device limited to `threads` worker threads (EmbreeDevice keeps its
  /// handle private to EmbreePeer.cpp), with `extraConfig` appended to its configuration as
  /// EmbreeDevice does.
  EmbreeFlatScene(int threads, const std::string& extraConfig);
  ~EmbreeFlatScene();
  EmbreeFlatScene(const EmbreeFlatScene&) = delete;
  EmbreeFlatScene& operator=(const EmbreeFlatScene&) = delete;

  /// Writes the world-space points of every listed instance of `scene` (committed) into the
  /// vertex buffer, in parallel over instances. The index buffer is written only when the
  /// instances' objects or sizes differ from the previous call (the first frame, or after the
  /// graph reclassified parts), as a flat renderer would keep its topology between frames.
  void flatten(const Scene& scene, std::span<const InstanceId> instances);
  /// rtcCommitGeometry + rtcCommitScene: a full LOW-quality rebuild over every triangle.
  void commit();

  /// Triangles written by the last flatten().
  std::size_t triangleCount() const;
  /// Number of flatten() calls that had to rewrite the index buffer.
  std::size_t topologyChanges() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tg::bench
