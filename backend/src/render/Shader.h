// Per-pixel tracing and shading behind Renderer: one Shader per frame, shared read-only by
// every tile task; all mutable state (traversal context, counters) belongs to the caller.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

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

/// What one light adds at a surface point, and the shadow ray that decides whether it does.
struct LightTerm {
  Vec3f local;                  ///< Phong contribution when unshadowed
  Ray shadow;                   ///< towards the light (valid when needsShadowRay)
  bool contributes = false;     ///< the light adds `local` (unless its shadow ray is blocked)
  bool needsShadowRay = false;  ///< Whitted mode, and the shadow ray has length
};

/// A surface point being shaded: the hit, its material and the facing normals.
struct SurfaceShading {
  SurfaceShading(const Ray& r, const Hit& h, const Scene::SurfaceData& s, const Material& m)
      : ray(r), hit(h), sd(s), material(m) {}
  const Ray& ray;
  const Hit& hit;
  const Scene::SurfaceData& sd;
  const Material& material;
  bool backFace = false;
  Vec3f ng, ns;                       ///< geometric and shading normal, facing the incoming ray
  Vec3f dir, v;                       ///< unit ray direction and the view vector (its negation)
  Vec3f diffuse;                      ///< diffuse colour after texturing
  Vec3f color;                        ///< accumulated: ambient, then the unshadowed light terms
  std::optional<SurfacePoint> point;  ///< refined hit point, computed on first use
};

/// Per-tile scratch memory of shadePrimaryBlock, reused from block to block.
struct BlockScratch {
  std::vector<LightTerm> terms;  ///< [light][lane]
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
  /// Shades the primary rays of up to kRayPacketSize neighbouring pixels whose hits were traced
  /// together: in Whitted mode the shadow rays towards each light go to the scene as one
  /// packet. out[k] equals shadePrimaryHit(rays[k], hits[k]) bit for bit.
  void shadePrimaryBlock(const Ray* rays, const Hit* hits, std::size_t n, TraversalContext& ctx,
                         TileCounters& counters, BlockScratch& scratch, PixelSample* out) const;

 private:
  /// The light arriving along `ray` (Whitted/OpenGL), `depth` bounces after the primary hit.
  Vec3f trace(const Ray& ray, int depth, float weight, TraversalContext& ctx,
              TileCounters& counters) const;
  /// The material and facing normals at a hit, with the ambient term.
  SurfaceShading prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd) const;
  /// The refined hit point of `sh`, computed once.
  const SurfacePoint& surface(SurfaceShading& sh) const;
  /// Calls fn(LightTerm, lightIndex) for every light that may add to the colour at `sh`, in
  /// light order, counting the shadow rays saved and traced.
  template <typename Fn>
  void forEachLightTerm(SurfaceShading& sh, TileCounters& counters, Fn&& fn) const;
  /// sh.color plus the reflected and refracted light (Whitted mode).
  Vec3f addSecondary(SurfaceShading& sh, int depth, float weight, TraversalContext& ctx,
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
