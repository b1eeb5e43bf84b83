/// @file FrameStats.h
/// Per-frame statistics written by `tg-render --stats`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "tracegraph/backend/render/RenderStats.h"

namespace tg {

/// Triangles held by instances of each dynamics class (instanced counts: a shared object
/// with three instances counts three times, as a flattened copy would).
struct TriangleCounts {
  std::size_t statics = 0;    ///< JSON "static"
  std::size_t rigid = 0;      ///< JSON "rigid"
  std::size_t deforming = 0;  ///< JSON "deforming"
};

/// What one frame cost. SceneGraph::sync fills everything but renderMs and rays, which the
/// renderer fills.
struct FrameStats {
  std::uint64_t frame = 0;    ///< frame number, 1 for the first sync
  double time = 0.0;          ///< clock time of the frame, seconds
  TriangleCounts triangles;   ///< triangles by dynamics class
  std::size_t instances = 0;  ///< backend instances
  /// Backend objects whose accelerator was built from scratch.
  std::size_t objectsRebuilt = 0;
  /// Deforming objects whose accelerator was refitted instead (same triangles, boxes updated;
  /// chosen by the backend while the tree's quality stays within bounds).
  std::size_t objectsRefitted = 0;
  /// Triangles in the rebuilt and the refitted objects.
  std::size_t trianglesRebuilt = 0;
  std::size_t reclassified = 0;  ///< nodes whose dynamics class changed this frame
  double syncMs = 0.0;           ///< whole sync, including rebuildMs and toplevelMs
  double rebuildMs = 0.0;        ///< object builds (parallel)
  double toplevelMs = 0.0;       ///< top-level build
  double renderMs = 0.0;         ///< filled by the renderer
  RayCounts rays;                ///< rays traced by kind, filled by the renderer
};

/// One frame as a single-line JSON object with the keys frame, time, triangles {static,
/// rigid, deforming}, instances, objects_rebuilt, triangles_rebuilt, reclassified, sync_ms,
/// rebuild_ms, toplevel_ms, render_ms, rays {primary, shadow, reflection, refraction, total}.
std::string toJson(const FrameStats& stats);

}  // namespace tg
