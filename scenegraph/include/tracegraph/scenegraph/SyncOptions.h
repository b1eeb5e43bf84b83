/// @file SyncOptions.h
/// Tuning of the classifier and the sync, fixed when a SceneGraph is created.
#pragma once

#include <cstdint>

#include "tracegraph/backend/Scene.h"

namespace tg {

/// Options of a SceneGraph.
struct SyncOptions {
  /// Options of the backend scene the graph is synced into.
  SceneOptions scene;
  /// Frames without change after which an observed moving transform or deforming mesh
  /// returns to static. Nodes driven by an animator never return.
  std::uint32_t restFrames = 30;
  /// Hysteresis: each earlier return to static doubles the rest needed next time, at most
  /// this many times (30 frames, then 60, 120, ...), so that a part moving every few frames
  /// settles as dynamic instead of being rebuilt back and forth.
  std::uint32_t maxRestDoublings = 4;
  /// Static geometry is merged into world-space chunks on a grid of this many cells per axis
  /// over the bounds of the first static geometry seen; a static part that starts moving
  /// rebuilds only its chunk. Cells outside those bounds continue the grid.
  std::uint32_t staticChunkGrid = 4;
};

}  // namespace tg
