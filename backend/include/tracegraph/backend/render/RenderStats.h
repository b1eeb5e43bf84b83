/// @file RenderStats.h
/// Per-frame statistics of the renderer.
#pragma once

#include <cstdint>

namespace tg {

/// Ray counts by kind. Integers only, so per-tile counts add up to the same totals in any
/// order and on any number of threads.
struct RayCounts {
  std::uint64_t primary = 0;     ///< camera rays
  std::uint64_t shadow = 0;      ///< rays towards lights (any-hit queries)
  std::uint64_t reflection = 0;  ///< mirror and Fresnel reflection rays
  std::uint64_t refraction = 0;  ///< rays transmitted into or out of glass

  /// Sum over all kinds.
  std::uint64_t total() const { return primary + shadow + reflection + refraction; }
  /// Adds another count kind by kind.
  RayCounts& operator+=(const RayCounts& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    return *this;
  }
  /// Equal in every kind.
  bool operator==(const RayCounts&) const = default;
};

/// What one render() did.
struct RenderStats {
  ///@{
  std::uint32_t width = 0, height = 0;  ///< image size in pixels
  ///@}
  int threads = 0;                      ///< maximum concurrency of the arena the frame rendered in
  double traceShadeMs = 0.0;            ///< wall time of tracing and shading all tiles
  double mraysPerSecond = 0.0;          ///< traced.total() / traceShadeMs, in millions per second

  /// Rays traced, by kind.
  RayCounts traced;
  /// Rays not traced because "model only what the scene needs" showed them useless:
  /// shadow: light behind the surface (N.L <= 0), outside a spot cone, black, or a material
  /// with zero contribution from it; reflection: hits on non-reflective materials;
  /// refraction: hits on opaque materials. (primary is always 0.) Whitted mode only.
  RayCounts saved;
  /// Secondary rays wanted by a material but not traced because of the depth limit.
  std::uint64_t depthLimited = 0;
  /// Secondary rays wanted but not traced because their weight fell below the cutoff.
  std::uint64_t weightCutoff = 0;
  /// Refractions that turned into total internal reflection (no refraction ray).
  std::uint64_t totalInternalReflections = 0;
  /// Accelerator work, summed over every ray.
  std::uint64_t triangleTests = 0;
  /// Accelerator nodes visited, summed over every ray.
  std::uint64_t nodeVisits = 0;
};

}  // namespace tg
