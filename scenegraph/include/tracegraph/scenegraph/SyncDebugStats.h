/// @file SyncDebugStats.h
/// Counters of what the last sync touched, for tests and profiling (not written by --stats).
#pragma once

#include <cstddef>

namespace tg {

/// What one SceneGraph::sync() did inside the graph. The point of these counters is to show
/// that a frame's work follows the number of changes, not the size of the graph.
struct SyncDebugStats {
  std::size_t dirtyNodes = 0;          ///< distinct nodes that notified since the last sync
  std::size_t nodesVisited = 0;        ///< dirty nodes handled + nodes re-traversed
  std::size_t regionsRetraversed = 0;  ///< Separator subtrees (or the root) walked again
  std::size_t framesUpdated = 0;       ///< instance matrices recomputed
  std::size_t deformingUpdated = 0;    ///< deforming objects given new points
  std::size_t chunksRebuilt = 0;       ///< static world-space chunks rebuilt
  /// Backend objects created.
  std::size_t objectsCreated = 0;
  /// Backend objects destroyed.
  std::size_t objectsDestroyed = 0;
  /// Backend instances created.
  std::size_t instancesCreated = 0;
  /// Backend instances destroyed.
  std::size_t instancesDestroyed = 0;
  std::size_t promoted = 0;       ///< static -> rigid/deforming this frame
  std::size_t demoted = 0;        ///< rigid/deforming -> static this frame
  std::size_t invalidShapes = 0;  ///< shapes skipped because their mesh is invalid
  double reclassifyMs = 0.0;      ///< re-traversal and rebuild preparation for reclassified nodes
};

}  // namespace tg
