// Whitted and OpenGL-like shading and the debug modes (see Shader.h).
#include <algorithm>
#include <cmath>
#include <optional>

#include "Shader.h"
#include "tracegraph/backend/render/Optics.h"

namespace tg::detail {
namespace {

/// One light as seen from a surface point.
struct LightSample {
  Vec3f direction;  ///< unit, from the point towards the light
  Vec3f color;      ///< what arrives: colour with attenuation and spot cone applied
  Vec3f position;   ///< the light's position (unused when atInfinity)
  bool atInfinity = false;
};

bool isBlack(const Vec3f& c) {
  return !(c.x > 0.0f || c.y > 0.0f || c.z > 0.0f);
}

/// Calls fn(LightSample, index) for every light of the scene, as seen from point p; `index`
/// numbers the lights point, directional, then spot (Shader::lightCount of them in all).
template <typename Fn>
void forEachLight(const RenderScene& rs, const Vec3f& p, Fn&& fn) {
  std::size_t index = 0;
  for (const PointLight& l : rs.pointLights) {
    const std::size_t i = index++;
    const Vec3f toLight = l.position - p;
    const float distance = length(toLight);
    if (!(distance > 0.0f)) continue;  // a light exactly at the point lights nothing
    LightSample s;
    s.direction = toLight / distance;
    s.color = l.attenuation.none() ? l.color : l.color * l.attenuation.factor(distance);
    s.position = l.position;
    fn(s, i);
  }
  for (const DirectionalLight& l : rs.directionalLights) {
    LightSample s;
    s.direction = -normalize(l.direction);
    s.color = l.color;
    s.atInfinity = true;
    fn(s, index++);
  }
  for (const SpotLight& l : rs.spotLights) {
    const std::size_t i = index++;
    const Vec3f toLight = l.position - p;
    const float distance = length(toLight);
    if (!(distance > 0.0f)) continue;
    LightSample s;
    s.direction = toLight / distance;
    s.color = l.color * (l.coneFactor(-s.direction) * l.attenuation.factor(distance));
    s.position = l.position;
    fn(s, i);
  }
}

/// Below this r.v, rv^shine is below 2^-160, where powf returns exactly +0 (it returns 0 once
/// its own shine * log2(rv), accurate to far better than the margin, reaches -150): the
/// highlight then adds +0, which changes no colour, and the call can be skipped. 0 (never
/// skip) for shine 0, where the power is 1.
float highlightCutoff(float shine) {
  return shine > 0.0f ? std::exp2(-160.0f / shine) : 0.0f;
}

/// Phong terms for unit normal n, unit view vector v and unit light vector l with nl = n.l > 0:
/// diffuse max(0, n.l) + specular max(0, r.v)^shine. A highlight needs r.v > 0, so 0^0 (shine
/// 0 facing away) counts as no highlight; below `cutoff` (see highlightCutoff) it is +0.
Vec3f phong(const Material& m, const Vec3f& diffuse, const Vec3f& n, const Vec3f& v, const Vec3f& l,
            float nl, float cutoff) {
  Vec3f c = diffuse * nl;
  if (m.reflective()) {
    const Vec3f r = n * (2.0f * nl) - l;
    const float rv = dot(r, v);
    if (rv > 0.0f && rv >= cutoff) c += m.specular * std::pow(rv, m.shine);
  }
  return c;
}

/// Colours of the `classes` mode.
Vec3f classColor(DynamicsClass c) {
  switch (c) {
    case DynamicsClass::Static:
      return {0.55f, 0.60f, 0.72f};
    case DynamicsClass::Rigid:
      return {0.30f, 0.80f, 0.35f};
    case DynamicsClass::Deforming:
      return {0.95f, 0.45f, 0.15f};
  }
  return {1.0f, 0.0f, 1.0f};
}

/// A well-mixed colour per id (murmur3's finaliser), each channel in [0.15, 0.95] so that no
/// instance is black or washed out.
Vec3f hashColor(std::uint32_t id) {
  std::uint32_t h = id + 0x9E3779B9u;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  auto channel = [](std::uint32_t bits) {
    return 0.15f + 0.8f * static_cast<float>(bits & 0xFFu) / 255.0f;
  };
  return {channel(h), channel(h >> 8), channel(h >> 16)};
}

}  // namespace

Shader::Shader(const RenderScene& scene, const RenderSettings& settings)
    : rs_(scene),
      scene_(*scene.scene),
      settings_(settings),
      whitted_(settings.mode == RenderMode::Whitted) {
  highlightCutoffs_.reserve(scene.materials.size());
  for (const Material& m : scene.materials) highlightCutoffs_.push_back(highlightCutoff(m.shine));
}

PixelSample Shader::shadePrimary(const Ray& ray, TraversalContext& ctx,
                                 TileCounters& counters) const {
  Hit hit;
  scene_.intersect(ray, hit, ctx);
  return shadePrimaryHit(ray, hit, ctx, counters);
}

PixelSample Shader::shadePrimaryHit(const Ray& ray, const Hit& hit, TraversalContext& ctx,
                                    TileCounters& counters) const {
  PixelSample s;
  ++counters.traced.primary;
  const bool debugMode = settings_.mode == RenderMode::Normals ||
                         settings_.mode == RenderMode::Classes ||
                         settings_.mode == RenderMode::Instances;
  if (!hit.valid()) {
    s.color = debugMode ? Vec3f{} : rs_.background;
    return s;
  }
  // Primary directions are unit, so t is the distance along the unit direction.
  s.depth = hit.t;
  s.instanceId = hit.instanceId;
  s.primId = hit.primId;
  const Scene::SurfaceData sd = scene_.surfaceAt(ray, hit);
  s.normal = sd.shadingNormal;
  s.color = debugMode ? debugColor(ray, hit, sd) : shadeHit(ray, hit, sd, 0, 1.0f, ctx, counters);
  return s;
}

Vec3f Shader::trace(const Ray& ray, int depth, float weight, TraversalContext& ctx,
                    TileCounters& counters) const {
  Hit hit;
  if (!scene_.intersect(ray, hit, ctx)) return rs_.background;
  return shadeHit(ray, hit, scene_.surfaceAt(ray, hit), depth, weight, ctx, counters);
}

bool Shader::mayTrace(int depth, float childWeight, TileCounters& counters) const {
  if (depth >= settings_.maxDepth) {
    ++counters.depthLimited;
    return false;
  }
  if (!(childWeight >= settings_.minWeight)) {
    ++counters.weightCutoff;
    return false;
  }
  return true;
}

SurfaceShading Shader::prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd) const {
  // RenderScene::material, keeping the index for the material's highlight cutoff.
  const std::uint32_t index = rs_.materialIndex(hit.instanceId, hit.objectId, hit.primId);
  const bool listed = index < rs_.materials.size();
  SurfaceShading sh{ray, hit, sd, listed ? rs_.materials[index] : defaultMaterial_};
  sh.highlightCutoff = listed ? highlightCutoffs_[index] : highlightCutoff(defaultMaterial_.shine);
  // Shade with the normals facing the incoming ray; the geometric normal alone decides the
  // side, because interpolated normals can disagree with it near silhouettes.
  sh.backFace = dot(sd.geometricNormal, ray.direction) > 0.0f;
  sh.ng = sh.backFace ? -sd.geometricNormal : sd.geometricNormal;
  sh.ns = sh.backFace ? -sd.shadingNormal : sd.shadingNormal;
  sh.dir = normalize(ray.direction);
  sh.v = -sh.dir;
  const Material& m = sh.material;
  sh.diffuse = m.diffuse;
  Vec3f ambient = m.ambient;
  if (m.texture != kInvalidId && sd.hasUv) {
    const Vec3f texel = rs_.textures[m.texture]->sample(sd.uv, settings_.textureFilter);
    sh.diffuse = m.textureMode == TextureMode::Replace ? texel : sh.diffuse * texel;
    ambient = ambient * texel;
  }
  sh.color = ambient * rs_.ambient;
  return sh;
}

const SurfacePoint& Shader::surface(SurfaceShading& sh) const {
  // The refined hit point is needed only for secondary rays; compute it at most once.
  if (!sh.point) sh.point = refineHitPoint(scene_, sh.ray, sh.hit);
  return *sh.point;
}

template <typename Slot, typename Fn>
void Shader::forEachLightTerm(SurfaceShading& sh, TileCounters& counters, Slot&& slot,
                              Fn&& fn) const {
  const bool lit = sh.material.lit();
  forEachLight(rs_, sh.sd.position, [&](const LightSample& light, std::size_t index) {
    const float nl = dot(sh.ns, light.direction);
    // Model only what the scene needs: no shadow ray when the light cannot change the colour.
    if (!lit || isBlack(light.color) || nl <= 0.0f || dot(sh.ng, light.direction) <= 0.0f) {
      if (whitted_) ++counters.saved.shadow;
      return;
    }
    const Vec3f local = light.color * phong(sh.material, sh.diffuse, sh.ns, sh.v, light.direction,
                                            nl, sh.highlightCutoff);
    if (isBlack(local)) {
      if (whitted_) ++counters.saved.shadow;
      return;
    }
    // Filled in place: a term built aside and then copied cost more than the Phong terms
    // (partial stores read back as one wide load stall the copy).
    LightTerm& term = slot(index);
    term.local = local;
    term.contributes = true;
    term.needsShadowRay = false;
    if (whitted_) {
      term.shadow = light.atInfinity ? spawnRay(surface(sh), light.direction)
                                     : spawnRayTo(surface(sh), light.position);
      if (term.shadow.tfar > 0.0f) {
        ++counters.traced.shadow;
        term.needsShadowRay = true;
      }
    }
    fn(term, index);
  });
}

Vec3f Shader::shadeHit(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd, int depth,
                       float weight, TraversalContext& ctx, TileCounters& counters) const {
  SurfaceShading sh = prepare(ray, hit, sd);
  LightTerm term;
  forEachLightTerm(
      sh, counters, [&](std::size_t) -> LightTerm& { return term; },
      [&](const LightTerm& t, std::size_t) {
        if (t.needsShadowRay && scene_.occluded(t.shadow, ctx)) return;
        sh.color += t.local;
      });
  return whitted_ ? addSecondary(sh, depth, weight, ctx, counters) : sh.color;
}

void Shader::collectLightTerms(SurfaceShading& sh, TileCounters& counters, LightTerm* terms) const {
  for (std::size_t j = 0, n = lightCount(); j < n; ++j) {
    terms[j].contributes = false;
    terms[j].needsShadowRay = false;
  }
  forEachLightTerm(
      sh, counters, [&](std::size_t index) -> LightTerm& { return terms[index]; },
      [](const LightTerm&, std::size_t) {});
}

std::size_t Shader::lightCount() const {
  return rs_.pointLights.size() + rs_.directionalLights.size() + rs_.spotLights.size();
}

Vec3f Shader::addSecondary(SurfaceShading& sh, int depth, float weight, TraversalContext& ctx,
                           TileCounters& counters) const {
  const SecondaryRays s = planSecondary(sh, depth, weight, counters);
  const Vec3f reflected =
      s.reflects ? trace(s.reflection, depth + 1, s.reflectionPathWeight, ctx, counters) : Vec3f{};
  const Vec3f refracted =
      s.refracts ? trace(s.refraction, depth + 1, s.refractionPathWeight, ctx, counters) : Vec3f{};
  return combineSecondary(sh.color, s, reflected, refracted);
}

SecondaryRays Shader::planSecondary(SurfaceShading& sh, int depth, float weight,
                                    TileCounters& counters) const {
  const Material& m = sh.material;
  const Vec3f& dir = sh.dir;
  const Vec3f& ns = sh.ns;
  const Vec3f& ng = sh.ng;
  const bool backFace = sh.backFace;
  SecondaryRays out;
  // Glass splits its transmittance T between reflection and refraction by Fresnel; the mirror
  // part (specular) adds to the reflection, traced as one ray.
  Vec3f reflectWeight = m.specular;
  float refractWeight = 0.0f;
  Vec3f refractDir;
  if (m.transmissive()) {
    // Entering or leaving is decided by the geometric normal; the outside is air.
    const float inside = m.effectiveIor();
    const float etaI = backFace ? inside : 1.0f, etaT = backFace ? 1.0f : inside;
    FresnelSplit split = fresnelRefract(dir, ns, etaI, etaT);
    // An interpolated normal can bend the refracted ray back to the incident side of the
    // actual surface; the geometric normal gives a direction that really crosses it.
    if (!split.totalInternalReflection && dot(split.refracted, ng) >= 0.0f)
      split = fresnelRefract(dir, ng, etaI, etaT);
    const float t = m.transmittance;
    reflectWeight += Vec3f{t, t, t} * split.reflectance;
    if (split.totalInternalReflection) {
      ++counters.totalInternalReflections;
    } else {
      refractWeight = t * split.transmittance;
      refractDir = split.refracted;
    }
  } else {
    ++counters.saved.refraction;
  }
  out.reflectWeight = reflectWeight;
  out.refractWeight = refractWeight;

  if (!isBlack(reflectWeight)) {
    const float childWeight = weight * maxComponent(reflectWeight);
    if (mayTrace(depth, childWeight, counters)) {
      Vec3f r = reflect(dir, ns);
      if (dot(r, ng) <= 0.0f) r = reflect(dir, ng);  // same reason as for refraction
      ++counters.traced.reflection;
      out.reflects = true;
      out.reflection = spawnRay(surface(sh), r);
      out.reflectionPathWeight = childWeight;
    }
  } else {
    ++counters.saved.reflection;
  }

  if (refractWeight > 0.0f) {
    const float childWeight = weight * refractWeight;
    if (mayTrace(depth, childWeight, counters)) {
      ++counters.traced.refraction;
      out.refracts = true;
      out.refraction = spawnRay(surface(sh), refractDir);
      out.refractionPathWeight = childWeight;
    }
  }
  return out;
}

Vec3f Shader::debugColor(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd) const {
  if (settings_.mode == RenderMode::Normals)
    return (sd.shadingNormal + Vec3f{1.0f, 1.0f, 1.0f}) * 0.5f;
  // A little headlight shading keeps shapes readable in the flat-colour modes.
  const float facing = std::abs(dot(sd.shadingNormal, normalize(ray.direction)));
  const Vec3f base = settings_.mode == RenderMode::Classes
                         ? classColor(rs_.dynamicsClass(hit.instanceId))
                         : hashColor(hit.instanceId);
  return base * (0.25f + 0.75f * facing);
}

}  // namespace tg::detail
