// Whitted shading of a whole tile, bounce depth by bounce depth (see Shader.h). The arithmetic
// is that of the recursive single-ray path (prepare, the light terms in light order,
// planSecondary, combineSecondary); only the order in which rays reach the scene changes.
// Neighbouring pixels' rays of one depth sit next to each other, so that the scene traces
// them as coherent packets: the shadow rays towards each light, then the reflection rays,
// then the refraction rays. Packets return exactly the hits and occlusions of single rays,
// so every pixel comes out bit for bit as from shadePrimaryHit.
#include <span>

#include "Shader.h"

namespace tg::detail {

void Shader::shadeWhittedTile(const Ray* rays, const Hit* hits, std::size_t n,
                              TraversalContext& ctx, TileCounters& counters, WaveScratch& scratch,
                              PixelSample* out) const {
  if (scratch.levels.empty()) scratch.levels.emplace_back();
  WaveScratch::Level& top = scratch.levels[0];
  top.rays.assign(rays, rays + n);
  top.hits.assign(hits, hits + n);
  top.weight.assign(n, 1.0f);
  top.cone.assign(n, 0.0f);
  counters.traced.primary += n;

  // Down: shade each depth and plan the next, until no ray is left.
  std::size_t deepest = 0;
  while (true) {
    shadeWaveLevel(deepest, ctx, counters, scratch);
    if (scratch.levels[deepest + 1].rays.empty()) break;
    ++deepest;
  }
  // Up: the colour along each ray from its own hit and its children's colours.
  for (std::size_t d = deepest + 1; d-- > 0;) {
    WaveScratch::Level& level = scratch.levels[d];
    const WaveScratch::Level& next = scratch.levels[d + 1];
    const std::size_t count = level.rays.size();
    level.color.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
      if (!level.shading[k]) {
        level.color[k] = rs_.background;
        continue;
      }
      const SecondaryRays& s = level.secondary[k];
      const Vec3f reflected = s.reflects ? next.color[level.reflectionChild[k]] : Vec3f{};
      const Vec3f refracted = s.refracts ? next.color[level.refractionChild[k]] : Vec3f{};
      level.color[k] = combineSecondary(level.shading[k]->color, s, reflected, refracted);
    }
  }

  for (std::size_t k = 0; k < n; ++k) {
    PixelSample& s = out[k];
    s = PixelSample{};
    s.color = top.color[k];
    if (!top.hits[k].valid()) continue;
    s.depth = top.hits[k].t;
    s.instanceId = top.hits[k].instanceId;
    s.primId = top.hits[k].primId;
    s.normal = top.sds[k]->shadingNormal;
  }
}

void Shader::shadeWaveLevel(std::size_t depth, TraversalContext& ctx, TileCounters& counters,
                            WaveScratch& scratch) const {
  // The next level first: a deque keeps `level` (and the references into it) in place.
  if (scratch.levels.size() < depth + 2) scratch.levels.emplace_back();
  WaveScratch::Level& level = scratch.levels[depth];
  WaveScratch::Level& next = scratch.levels[depth + 1];
  next.rays.clear();
  next.weight.clear();
  next.cone.clear();

  const std::size_t n = level.rays.size();
  if (depth > 0) {
    level.hits.resize(n);
    scene_.intersect(std::span<const Ray>(level.rays), std::span<Hit>(level.hits), ctx);
  }
  // Sized once, never resized while shading refers into them. Only `shading` is cleared: it
  // tells the hits apart, and the other tables are written for every hit before being read.
  level.sds.resize(n);
  level.shading.clear();
  level.shading.resize(n);
  level.secondary.resize(n);
  level.reflectionChild.resize(n);
  level.refractionChild.resize(n);

  // Every hit's light terms, with their shadow rays.
  const std::size_t lights = lightCount();
  // Not cleared: collectLightTerms resets the flags of every hit's terms, and only hits' terms
  // are read (clearing the whole table cost more than filling it).
  scratch.terms.resize(lights * n);
  level.hitRays.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (!level.hits[k].valid()) continue;
    level.hitRays.push_back(static_cast<std::uint32_t>(k));
    level.sds[k] = scene_.surfaceAt(level.rays[k], level.hits[k]);
    level.shading[k].emplace(prepare(level.rays[k], level.hits[k], *level.sds[k], level.cone[k]));
    collectLightTerms(*level.shading[k], counters, scratch.terms.data() + k * lights);
  }
  // The shadow rays towards one light, in ray order, to the scene together.
  for (std::size_t j = 0; j < lights; ++j) {
    scratch.shadowRays.clear();
    scratch.shadowOwner.clear();
    for (const std::uint32_t k : level.hitRays)
      if (const LightTerm& term = scratch.terms[k * lights + j]; term.needsShadowRay) {
        scratch.shadowRays.push_back(term.shadow);
        scratch.shadowOwner.push_back(k);
      }
    if (scratch.shadowRays.empty()) continue;
    scratch.blocked.resize(scratch.shadowRays.size());
    scene_.occluded(std::span<const Ray>(scratch.shadowRays),
                    std::span<std::uint8_t>(scratch.blocked), ctx);
    for (std::size_t i = 0; i < scratch.shadowRays.size(); ++i)
      if (scratch.blocked[i])
        scratch.terms[scratch.shadowOwner[i] * lights + j].contributes = false;
  }
  // The lights in order (the single-ray sum's order), then the rays leaving each hit.
  for (const std::uint32_t k : level.hitRays) {
    SurfaceShading& sh = *level.shading[k];
    for (std::size_t j = 0; j < lights; ++j) {
      const LightTerm& term = scratch.terms[k * lights + j];
      if (term.contributes) sh.color += term.local;
    }
    level.secondary[k] = planSecondary(sh, static_cast<int>(depth), level.weight[k], counters);
  }
  // All reflection rays, then all refraction rays: neighbours of one kind stay together.
  // `secondary` holds this level's plans for hits only (misses keep an earlier tile's).
  for (const std::uint32_t k : level.hitRays)
    if (level.secondary[k].reflects) {
      level.reflectionChild[k] = static_cast<std::uint32_t>(next.rays.size());
      next.rays.push_back(level.secondary[k].reflection);
      next.weight.push_back(level.secondary[k].reflectionPathWeight);
      next.cone.push_back(level.shading[k]->coneWidth);
    }
  for (const std::uint32_t k : level.hitRays)
    if (level.secondary[k].refracts) {
      level.refractionChild[k] = static_cast<std::uint32_t>(next.rays.size());
      next.rays.push_back(level.secondary[k].refraction);
      next.weight.push_back(level.secondary[k].refractionPathWeight);
      next.cone.push_back(level.shading[k]->coneWidth);
    }
}

}  // namespace tg::detail
