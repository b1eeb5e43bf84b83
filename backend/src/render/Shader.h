// Per-pixel tracing and shading behind Renderer: one Shader per frame, shared read-only by
// every tile task; all mutable state (traversal context, counters) belongs to the caller.
#pragma once

#include <cstdint>

#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/render/RayOffset.h"
#include "tracegraph/backend/render/RenderScene.h"
#include "tracegraph/backend/render/Renderer.h"

namespace tg::detail {

/// Counts of one tile, summed into RenderStats after the parallel loop.
struct TileCounters {
  RayCounts traced;
  RayCounts saved;
  std::uint64_t depthLimited = 0;
  std::uint64_t weightCutoff = 0;
  std::uint64_t totalInternalReflections = 0;
};

/// Everything a pixel contributes to the frame's images.
struct PixelSample {
  Vec3f color;
  float depth = kInfinity;
  Vec3f normal;
  std::uint32_t instanceId = kInvalidId;
  std::uint32_t primId = kInvalidId;
};

/// Traces and shades rays for one mode.
class Shader {
 public:
  Shader(const RenderScene& scene, const RenderSettings& settings);

  /// Traces a primary ray and shades it in the configured mode.
  PixelSample shadePrimary(const Ray& ray, TraversalContext& ctx, TileCounters& counters) const;
  /// Shades a primary ray whose closest hit `hit` (invalid: a miss) was already traced, e.g.
  /// in a packet.
  PixelSample shadePrimaryHit(const Ray& ray, const Hit& hit, TraversalContext& ctx,
                              TileCounters& counters) const;

 private:
  /// The light arriving along `ray` (Whitted/OpenGL), `depth` bounces after the primary hit.
  Vec3f trace(const Ray& ray, int depth, float weight, TraversalContext& ctx,
              TileCounters& counters) const;
  /// Phong shading plus, in Whitted mode, shadows, reflection and refraction at `hit`.
  Vec3f shadeHit(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd, int depth,
                 float weight, TraversalContext& ctx, TileCounters& counters) const;
  /// True when a secondary ray of weight `childWeight` may leave a hit `depth` bounces deep;
  /// otherwise counts why not.
  bool mayTrace(int depth, float childWeight, TileCounters& counters) const;
  /// Colour of the debug modes (normals, classes, instances).
  Vec3f debugColor(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd) const;

  const RenderScene& rs_;
  const Scene& scene_;
  RenderSettings settings_;
  bool whitted_;
};

}  // namespace tg::detail
