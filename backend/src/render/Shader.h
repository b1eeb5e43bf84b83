// Per-pixel tracing and shading behind Renderer: one Shader per frame, shared read-only by
// every tile task; all mutable state (traversal context, counters) belongs to the caller.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "LightTerms.h"
#include "MaterialRangeIndex.h"
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

/// Where a material's Phong highlight cannot change a colour, so that its power need not be
/// computed (see highlightLimits in Shading.cpp).
struct HighlightLimits {
  float cutoff = 0.0f;  ///< r.v below which the highlight is exactly +0
  /// r.v below which the highlight is at most specular * 2^-32 (0: never)...
  float negligibleBelow = 0.0f;
  /// ... which a diffuse term (per channel) above 0 and at least specular * 2^-7 absorbs
  /// exactly: the highlight stays below half an ulp of it.
  Vec3f absorbingDiffuse;
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
  /// Origins of rays leaving `point` above (0) and below (1) the surface (offsetRayOrigin),
  /// each made on first use: the shadow rays of every light on one side share one.
  Vec3f spawnOrigin[2];
  unsigned spawnOriginsMade = 0;  ///< bit s set once spawnOrigin[s] is made
  HighlightLimits highlight;      ///< of the material
  /// Width of the ray's cone at the hit (ray cones; 0 unless textures are mip-mapped).
  float coneWidth = 0.0f;
};

/// The secondary rays a hit spawns in Whitted mode, and how their colours are weighed.
struct SecondaryRays {
  Vec3f reflectWeight;         ///< multiplies the reflected colour
  float refractWeight = 0.0f;  ///< multiplies the refracted colour
  Ray reflection, refraction;  ///< valid when reflects / refracts
  float reflectionPathWeight = 0.0f, refractionPathWeight = 0.0f;  ///< for the ray-weight cutoff
  bool reflects = false, refracts = false;
};

/// `local` plus the reflected and refracted colours weighed as `s` says, added in one fixed
/// order, so that the recursive and the level-by-level paths give the same bits.
inline Vec3f combineSecondary(const Vec3f& local, const SecondaryRays& s, const Vec3f& reflected,
                              const Vec3f& refracted) {
  Vec3f color = local;
  if (s.reflects) color += s.reflectWeight * reflected;
  if (s.refracts) color += refracted * s.refractWeight;
  return color;
}

/// Per-tile scratch memory of shadeWhittedTile, reused from tile to tile (see ShadingWave.cpp).
struct WaveScratch {
  /// The rays of one bounce depth of a tile, and how each came about.
  struct Level {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<float> weight;  ///< path weight of the ray
    std::vector<float> cone;    ///< width of the ray's cone where it starts
    std::vector<std::optional<Scene::SurfaceData>> sds;
    std::vector<std::optional<SurfaceShading>> shading;  ///< refers to rays, hits and sds
    std::vector<SecondaryRays> secondary;
    std::vector<std::uint32_t> reflectionChild, refractionChild;  ///< into the next level
    std::vector<Vec3f> color;  ///< the light arriving along each ray
    /// The rays that hit something, in order: the loops over a level's hits (one per light
    /// among them) read this instead of testing every ray's `shading`, a wide entry each.
    std::vector<std::uint32_t> hitRays;
  };
  /// Levels by depth; a deque, so that adding one never moves the others.
  std::deque<Level> levels;
  std::vector<LightTerm> terms;  ///< [ray][light] of the level being shaded
  std::vector<Ray> shadowRays;
  std::vector<std::uint32_t> shadowOwner;  ///< the ray of the level each shadow ray serves
  std::vector<std::uint8_t> blocked;
};

/// Traces and shades rays for one mode.
class Shader {
 public:
  /// `pixelSpread` is Camera::pixelSpreadAngle of the frame's camera: primary rays' texture
  /// footprints grow with it (ray cones).
  Shader(const RenderScene& scene, const RenderSettings& settings, float pixelSpread);

  /// Traces a primary ray and shades it in the configured mode.
  PixelSample shadePrimary(const Ray& ray, TraversalContext& ctx, TileCounters& counters) const;
  /// Shades a primary ray whose closest hit `hit` (invalid: a miss) was already traced, e.g.
  /// in a packet.
  PixelSample shadePrimaryHit(const Ray& ray, const Hit& hit, TraversalContext& ctx,
                              TileCounters& counters) const;
  /// True when shadeWhittedTile applies (Whitted mode).
  bool shadesByWave() const { return whitted_; }
  /// True when shadeOpenGlTile applies (OpenGL mode); the debug modes shade pixel by pixel.
  bool shadesOpenGlTiles() const { return settings_.mode == RenderMode::OpenGL; }
  /// Shades the `n` primary rays of a tile in OpenGL mode, whose hits were traced already,
  /// several pixels at a time: the point lights' terms are summed with the pixels in SIMD lanes.
  /// out[k] equals shadePrimaryHit(rays[k], hits[k]) bit for bit.
  void shadeOpenGlTile(const Ray* rays, const Hit* hits, std::size_t n, TileCounters& counters,
                       PixelSample* out) const;
  /// Shades the `n` primary rays of a tile, whose hits were traced already, bounce depth by
  /// bounce depth: the rays of one depth (reflection, refraction, and the shadow rays towards
  /// each light) go to the scene together as packets of neighbouring rays. out[k] equals
  /// shadePrimaryHit(rays[k], hits[k]) bit for bit.
  void shadeWhittedTile(const Ray* rays, const Hit* hits, std::size_t n, TraversalContext& ctx,
                        TileCounters& counters, WaveScratch& scratch, PixelSample* out) const;

 private:
  /// The light arriving along `ray` (Whitted/OpenGL), `depth` bounces after the primary hit;
  /// `cone` is the width of the ray's cone where it starts.
  Vec3f trace(const Ray& ray, int depth, float weight, float cone, TraversalContext& ctx,
              TileCounters& counters) const;
  /// The material and facing normals at a hit of a ray whose cone is `cone` wide where it
  /// starts, with the ambient term.
  SurfaceShading prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd,
                         float cone) const;
  /// prepare with the hit's material index already found (materialIndexOf).
  SurfaceShading prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd, float cone,
                         std::uint32_t materialIndex) const;
  /// The index into RenderScene::materials of the material at `hit` (RenderScene::material's
  /// rules); out of range for the default material.
  std::uint32_t materialIndexOf(const Hit& hit) const;
  /// Asks the cache for the texels that prepare will read at a hit with material
  /// `materialIndex` and surface `sd` (Texture::prefetch): a hint, which changes no result.
  void prefetchTexels(std::uint32_t materialIndex, const Scene::SurfaceData& sd) const;
  /// The mip level of `texture` for the footprint of the ray cone of `sh` (Ray Tracing Gems'
  /// ray cones, sized by the footprint's area on the surface; see Shading.cpp); -inf or NaN
  /// where it is unknown (level 0 is then read).
  float textureLod(const SurfaceShading& sh, const Texture& texture) const;
  /// The refined hit point of `sh`, computed once.
  const SurfacePoint& surface(SurfaceShading& sh) const;
  /// For every light that may add to the colour at `sh`, in light order: fills the term
  /// slot(lightIndex) returns, then calls fn(term, lightIndex); counts the shadow rays saved
  /// and traced.
  template <typename Slot, typename Fn>
  void forEachLightTerm(SurfaceShading& sh, TileCounters& counters, Slot&& slot, Fn&& fn) const;
  /// Fills terms[j] for every light j that may add to the colour at `sh`, as forEachLightTerm
  /// finds them; the others only have their flags cleared.
  void collectLightTerms(SurfaceShading& sh, TileCounters& counters, LightTerm* terms) const;
  /// sh.color plus every light's term at `sh`, unshadowed (OpenGL mode): what shadeHit sums
  /// through forEachLightTerm when no light needs a shadow ray.
  Vec3f unshadowedColor(const SurfaceShading& sh) const;
  /// Calls fn(first, present, added, rgb) for each group of point lights in light order, with
  /// the terms at `sh` of lights first + j (LightGroupTerms: bit j of present and added, and
  /// row j of rgb), computed several lights at a time.
  template <typename Fn>
  void forEachPointLightGroup(const SurfaceShading& sh, Fn&& fn) const;
  /// shadeOpenGlTile, W pixels at a time; sums(lanes) adds the point lights' terms.
  template <std::size_t W, typename Sums>
  void shadeOpenGlLanes(const Ray* rays, const Hit* hits, std::size_t n, TileCounters& counters,
                        PixelSample* out, Sums&& sums) const;
  /// Number of lights of the scene (point, directional and spot).
  std::size_t lightCount() const;
  /// sh.color plus the reflected and refracted light (Whitted mode).
  Vec3f addSecondary(SurfaceShading& sh, int depth, float weight, TraversalContext& ctx,
                     TileCounters& counters) const;
  /// The reflection and refraction rays leaving `sh` (a hit `depth` bounces deep whose path
  /// has weight `weight`), counting those traced and those not.
  SecondaryRays planSecondary(SurfaceShading& sh, int depth, float weight,
                              TileCounters& counters) const;
  /// Shades level `depth` of the scratch: traces its rays (depth >= 1), gathers its shadow
  /// rays by light, and plans the next level's rays.
  void shadeWaveLevel(std::size_t depth, TraversalContext& ctx, TileCounters& counters,
                      WaveScratch& scratch) const;
  /// Phong shading plus, in Whitted mode, shadows, reflection and refraction at `hit`.
  Vec3f shadeHit(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd, int depth,
                 float weight, float cone, TraversalContext& ctx, TileCounters& counters) const;
  /// True when a secondary ray of weight `childWeight` may leave a hit `depth` bounces deep;
  /// otherwise counts why not.
  bool mayTrace(int depth, float childWeight, TileCounters& counters) const;
  /// Colour of the debug modes (normals, classes, instances).
  Vec3f debugColor(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd) const;

  const RenderScene& rs_;
  const Scene& scene_;
  RenderSettings settings_;
  bool whitted_;
  std::vector<HighlightLimits> highlightLimits_;  ///< by material index (see Shading.cpp)
  /// By instance: an index over RenderScene::instanceMaterialRanges (empty where it is).
  std::vector<MaterialRangeIndex> rangeIndex_;
  Material defaultMaterial_{};  ///< for hits without a material, as RenderScene gives
  float pixelSpread_;           ///< the camera's ray-cone spread angle per pixel, in radians
  /// rs_.pointLights by four, for the baseline light terms (when pointTerms8_ is null).
  std::vector<PointLightGroup<4>> pointGroups4_;
  /// rs_.pointLights by eight, for pointTerms8_.
  std::vector<PointLightGroup<8>> pointGroups8_;
  /// The eight-light terms of a wider instruction set, or null.
  PointLightTerms8Fn pointTerms8_ = nullptr;
  /// rs_.pointLights as plain numbers, for the sums over pixels.
  std::vector<PlainPointLight> plainLights_;
  /// The sums over eight pixels of a wider instruction set (where pointTerms8_ is set), or null.
  PointLightSums8Fn pointSums8_ = nullptr;
};

}  // namespace tg::detail
