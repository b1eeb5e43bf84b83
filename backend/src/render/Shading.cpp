// Whitted and OpenGL-like shading and the debug modes (see Shader.h).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <new>
#include <optional>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "PointLightTermsImpl.h"
#include "Shader.h"
#include "tracegraph/backend/Simd.h"
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

/// Calls fn(LightSample, index) for every directional and spot light of the scene, as seen
/// from point p; `index` numbers the lights point (done by pointLightTerms), directional, then
/// spot (Shader::lightCount of them in all).
template <typename Fn>
void forEachOtherLight(const RenderScene& rs, const Vec3f& p, Fn&& fn) {
  std::size_t index = rs.pointLights.size();
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

/// The cutoff, and where a highlight is too small to change the diffuse term it is added to.
/// Below negligibleBelow = 2^(-34 / shine) (rounded to float: relative error 2^-24, which moves
/// the bound on the power by less than a factor 2 up to shine 2^23), rv^shine < 2^-33 and powf
/// (error under one ulp) returns at most 2^-32. The highlight specular * powf is then at most
/// specular * 2^-32 (2^-32 scales exactly); for a diffuse term c >= specular * 2^-7 = 2^25 times
/// that, it is below c * 2^-25, under half an ulp of c, so c + highlight rounds to c itself.
/// c must also be > 0: adding a +0 highlight to -0 would give +0. The profile of the kitchen
/// has most powers in that range.
HighlightLimits highlightLimits(const Material& m) {
  HighlightLimits h;
  h.cutoff = highlightCutoff(m.shine);
  const Vec3f absorbing = m.specular * 0x1p-7f;
  // Only when scaling by 2^-7 lost no bits (not for denormal or flushed specular values).
  if (m.shine > 0.0f && m.shine <= 0x1p23f && absorbing * 0x1p7f == m.specular) {
    h.negligibleBelow = static_cast<float>(std::exp2(-34.0 / static_cast<double>(m.shine)));
    h.absorbingDiffuse = absorbing;
  }
  return h;
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

/// What a directional or spot light adds at `sh` (forEachLightTerm's term), or nothing when it
/// cannot change the colour there.
std::optional<Vec3f> otherLightTerm(const SurfaceShading& sh, const LightSample& light) {
  const float nl = dot(sh.ns, light.direction);
  if (!sh.material.lit() || isBlack(light.color) || nl <= 0.0f ||
      dot(sh.ng, light.direction) <= 0.0f)
    return std::nullopt;
  const Vec3f local = light.color * phong(sh.material, sh.diffuse, sh.ns, sh.v, light.direction, nl,
                                          sh.highlight.cutoff);
  if (isBlack(local)) return std::nullopt;
  return local;
}

#if defined(__SSE2__)
/// Four floats, one per light of a PointLightGroup<4>. Every operation is the IEEE operation of
/// the scalar code, lane by lane, so a lane holds bit for bit what the scalar code computes.
struct Lanes4 {
  static constexpr std::size_t kWidth = 4;
  __m128 v;

  static Lanes4 load(const float* a) { return {_mm_loadu_ps(a)}; }
  static Lanes4 splat(float f) { return {_mm_set1_ps(f)}; }
  /// Lanes f(0) to f(3), put together in registers: stored one by one and loaded as a vector,
  /// they would wait for the stores to retire (no store forwarding).
  template <typename F>
  static Lanes4 fromScalars(const F& f) {
    return {_mm_setr_ps(f(0), f(1), f(2), f(3))};
  }
  static void store(const Lanes4& a, float* out) { _mm_storeu_ps(out, a.v); }
  /// A true/false per lane, as SSE comparisons give it (all bits set or clear).
  struct Mask {
    __m128 v;
  };
  static Mask allLanes(bool on) { return {_mm_castsi128_ps(_mm_set1_epi32(on ? -1 : 0))}; }
  /// Lane j true when bit j of `b` is set.
  static Mask fromBits(unsigned b) {
    const __m128i lane = _mm_setr_epi32(1, 2, 4, 8);
    const __m128i set = _mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), lane);
    return {_mm_castsi128_ps(_mm_cmpeq_epi32(set, lane))};
  }
};
Lanes4 operator+(Lanes4 a, Lanes4 b) {
  return {_mm_add_ps(a.v, b.v)};
}
Lanes4 operator-(Lanes4 a, Lanes4 b) {
  return {_mm_sub_ps(a.v, b.v)};
}
Lanes4 operator*(Lanes4 a, Lanes4 b) {
  return {_mm_mul_ps(a.v, b.v)};
}
Lanes4 operator/(Lanes4 a, Lanes4 b) {
  return {_mm_div_ps(a.v, b.v)};
}
Lanes4 sqrt(Lanes4 a) {
  return {_mm_sqrt_ps(a.v)};
}
Lanes4::Mask operator>(Lanes4 a, Lanes4 b) {
  return {_mm_cmpgt_ps(a.v, b.v)};
}
Lanes4::Mask operator>=(Lanes4 a, Lanes4 b) {
  return {_mm_cmpge_ps(a.v, b.v)};
}
Lanes4::Mask operator<=(Lanes4 a, Lanes4 b) {
  return {_mm_cmple_ps(a.v, b.v)};
}
Lanes4::Mask operator|(Lanes4::Mask a, Lanes4::Mask b) {
  return {_mm_or_ps(a.v, b.v)};
}
Lanes4::Mask operator&(Lanes4::Mask a, Lanes4::Mask b) {
  return {_mm_and_ps(a.v, b.v)};
}
/// a and not b.
Lanes4::Mask andNot(Lanes4::Mask a, Lanes4::Mask b) {
  return {_mm_andnot_ps(b.v, a.v)};
}
/// Bit j set when lane j is true.
unsigned bits(Lanes4::Mask m) {
  return static_cast<unsigned>(_mm_movemask_ps(m.v));
}
/// a where m is true, b elsewhere.
Lanes4 select(Lanes4::Mask m, Lanes4 a, Lanes4 b) {
  return {_mm_or_ps(_mm_and_ps(m.v, a.v), _mm_andnot_ps(m.v, b.v))};
}
/// out[j] = (r[j], g[j], b[j], 0): lane j's colour as one 16-byte store.
void storeColors(Lanes4 r, Lanes4 g, Lanes4 b, float (&out)[4][4]) {
  __m128 x = r.v, y = g.v, z = b.v, w = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(x, y, z, w);
  _mm_storeu_ps(out[0], x);
  _mm_storeu_ps(out[1], y);
  _mm_storeu_ps(out[2], z);
  _mm_storeu_ps(out[3], w);
}
#else
/// Four floats, one per light of a PointLightGroup<4> (portable fallback of the SSE version).
struct Lanes4 {
  static constexpr std::size_t kWidth = 4;
  std::array<float, 4> v;

  static Lanes4 load(const float* a) { return {{a[0], a[1], a[2], a[3]}}; }
  static Lanes4 splat(float f) { return {{f, f, f, f}}; }
  template <typename F>
  static Lanes4 fromScalars(const F& f) {
    return {{f(0), f(1), f(2), f(3)}};
  }
  static void store(const Lanes4& a, float* out) {
    for (std::size_t j = 0; j < 4; ++j) out[j] = a.v[j];
  }
  /// A true/false per lane, as bits.
  struct Mask {
    unsigned v;
  };
  static Mask allLanes(bool on) { return {on ? 15u : 0u}; }
  static Mask fromBits(unsigned b) { return {b & 15u}; }
};
template <typename F>
Lanes4 laneWise(F&& f) {
  Lanes4 r;
  for (std::size_t j = 0; j < 4; ++j) r.v[j] = f(j);
  return r;
}
template <typename F>
Lanes4::Mask maskWise(F&& f) {
  unsigned m = 0;
  for (std::size_t j = 0; j < 4; ++j) m |= f(j) ? 1u << j : 0u;
  return {m};
}
Lanes4 operator+(Lanes4 a, Lanes4 b) {
  return laneWise([&](std::size_t j) { return a.v[j] + b.v[j]; });
}
Lanes4 operator-(Lanes4 a, Lanes4 b) {
  return laneWise([&](std::size_t j) { return a.v[j] - b.v[j]; });
}
Lanes4 operator*(Lanes4 a, Lanes4 b) {
  return laneWise([&](std::size_t j) { return a.v[j] * b.v[j]; });
}
Lanes4 operator/(Lanes4 a, Lanes4 b) {
  return laneWise([&](std::size_t j) { return a.v[j] / b.v[j]; });
}
Lanes4 sqrt(Lanes4 a) {
  return laneWise([&](std::size_t j) { return std::sqrt(a.v[j]); });
}
Lanes4::Mask operator>(Lanes4 a, Lanes4 b) {
  return maskWise([&](std::size_t j) { return a.v[j] > b.v[j]; });
}
Lanes4::Mask operator>=(Lanes4 a, Lanes4 b) {
  return maskWise([&](std::size_t j) { return a.v[j] >= b.v[j]; });
}
Lanes4::Mask operator<=(Lanes4 a, Lanes4 b) {
  return maskWise([&](std::size_t j) { return a.v[j] <= b.v[j]; });
}
Lanes4::Mask operator|(Lanes4::Mask a, Lanes4::Mask b) {
  return {a.v | b.v};
}
Lanes4::Mask operator&(Lanes4::Mask a, Lanes4::Mask b) {
  return {a.v & b.v};
}
Lanes4::Mask andNot(Lanes4::Mask a, Lanes4::Mask b) {
  return {a.v & ~b.v};
}
unsigned bits(Lanes4::Mask m) {
  return m.v;
}
Lanes4 select(Lanes4::Mask m, Lanes4 a, Lanes4 b) {
  return laneWise([&](std::size_t j) { return (m.v >> j & 1u) ? a.v[j] : b.v[j]; });
}
void storeColors(Lanes4 r, Lanes4 g, Lanes4 b, float (&out)[4][4]) {
  for (std::size_t j = 0; j < 4; ++j) {
    out[j][0] = r.v[j];
    out[j][1] = g.v[j];
    out[j][2] = b.v[j];
    out[j][3] = 0.0f;
  }
}
#endif

/// `lights` as groups of W.
template <std::size_t W>
void groupLights(const std::vector<PointLight>& lights, std::vector<PointLightGroup<W>>& groups) {
  groups.assign((lights.size() + W - 1) / W, PointLightGroup<W>{});
  for (std::size_t i = 0; i < groups.size() * W; ++i) {
    const PointLight& l = lights[std::min(i, lights.size() - 1)];
    PointLightGroup<W>& q = groups[i / W];
    const std::size_t j = i % W;
    q.x[j] = l.position.x;
    q.y[j] = l.position.y;
    q.z[j] = l.position.z;
    q.r[j] = l.color.x;
    q.g[j] = l.color.y;
    q.b[j] = l.color.z;
    q.attenuated = q.attenuated || !l.attenuation.none();
  }
}

/// The point-light inputs of `sh` as the light-term kernels read them.
LightTermsPoint lightTermsPoint(const SurfaceShading& sh) {
  LightTermsPoint p;
  const Material& m = sh.material;
  for (int a = 0; a < 3; ++a) {
    const auto c = static_cast<std::size_t>(a);
    p.position[a] = sh.sd.position[c];
    p.ns[a] = sh.ns[c];
    p.ng[a] = sh.ng[c];
    p.v[a] = sh.v[c];
    p.diffuse[a] = sh.diffuse[c];
    p.specular[a] = m.specular[c];
    p.absorbingDiffuse[a] = sh.highlight.absorbingDiffuse[c];
  }
  p.shine = m.shine;
  p.lit = m.lit();
  p.reflective = m.reflective();
  p.cutoff = sh.highlight.cutoff;
  p.negligibleBelow = sh.highlight.negligibleBelow;
  return p;
}

/// The terms of the `count` lights of group `q` (`lights` the first of them) at `p`, four at a
/// time (pointLightTermsWith), with the lights' distance attenuation applied lane by lane.
void pointLightTerms4(const PointLightGroup<4>& q, const PointLight* lights, std::size_t count,
                      const LightTermsPoint& p, LightGroupTerms<4>& out) {
  const auto attenuate = [&](const Lanes4& distance, Lanes4& cr, Lanes4& cg, Lanes4& cb) {
    float d[4];
    Lanes4::store(distance, d);
    Vec3f c[4];
    for (std::size_t j = 0; j < 4; ++j) {
      c[j] = j < count && !lights[j].attenuation.none()
                 ? lights[j].color * lights[j].attenuation.factor(d[j])
                 : Vec3f{q.r[j], q.g[j], q.b[j]};
    }
    cr = Lanes4::fromScalars([&](std::size_t j) { return c[j].x; });
    cg = Lanes4::fromScalars([&](std::size_t j) { return c[j].y; });
    cb = Lanes4::fromScalars([&](std::size_t j) { return c[j].z; });
  };
  pointLightTermsWith<Lanes4>(q, count, p, attenuate, out);
}

/// log2(x) within 0.01 for normal x > 0 (exponent plus a quadratic in the mantissa), -inf for
/// zeros and denormals, NaN for negative x and NaN, +inf for +inf: good enough to choose a mip
/// level, and a fraction of std::log2's cost.
float roughLog2(float x) {
  if (!(x >= 0x1p-126f)) return x >= 0.0f ? -kInfinity : std::numeric_limits<float>::quiet_NaN();
  if (x == kInfinity) return kInfinity;
  const auto bits = std::bit_cast<std::uint32_t>(x);
  const auto exponent = static_cast<float>(static_cast<std::int32_t>(bits >> 23) - 127);
  const float m = std::bit_cast<float>((bits & 0x007FFFFFu) | 0x3F800000u) - 1.0f;  // [0, 1)
  // log2(1 + m) ~ m (1.3466 - 0.3466 m): exact at 0 and 1, off by < 0.0075 between.
  return exponent + m * (1.3466f - 0.3466f * m);
}

/// Lane j of `rows` set to `value`.
template <std::size_t W>
void setLane(float (&rows)[3][W], std::size_t j, const Vec3f& value) {
  rows[0][j] = value.x;
  rows[1][j] = value.y;
  rows[2][j] = value.z;
}

/// Lane j of `p` from the surface point being shaded in `sh`, with its colour so far.
template <std::size_t W>
void setLane(SurfacePointLanes<W>& p, std::size_t j, const SurfaceShading& sh) {
  const Material& m = sh.material;
  setLane(p.position, j, sh.sd.position);
  setLane(p.ns, j, sh.ns);
  setLane(p.ng, j, sh.ng);
  setLane(p.v, j, sh.v);
  setLane(p.diffuse, j, sh.diffuse);
  setLane(p.specular, j, m.specular);
  setLane(p.absorbingDiffuse, j, sh.highlight.absorbingDiffuse);
  setLane(p.color, j, sh.color);
  p.shine[j] = m.shine;
  p.cutoff[j] = sh.highlight.cutoff;
  p.negligibleBelow[j] = sh.highlight.negligibleBelow;
  if (m.lit()) p.lit |= 1u << j;
  if (m.reflective()) p.reflective |= 1u << j;
}

/// The sums of pointLightSumsWith over four pixels, with the lights' distance attenuation
/// applied lane by lane as pointLightTerms4 applies it.
void pointLightSums4(const std::vector<PointLight>& lights, const PlainPointLight* plain,
                     SurfacePointLanes<4>& p) {
  const auto attenuate = [&](std::size_t i, const Lanes4& distance, Lanes4& cr, Lanes4& cg,
                             Lanes4& cb) {
    const PointLight& l = lights[i];
    if (l.attenuation.none()) return;
    float d[4];
    Lanes4::store(distance, d);
    Vec3f c[4];
    for (std::size_t j = 0; j < 4; ++j) c[j] = l.color * l.attenuation.factor(d[j]);
    cr = Lanes4::fromScalars([&](std::size_t j) { return c[j].x; });
    cg = Lanes4::fromScalars([&](std::size_t j) { return c[j].y; });
    cb = Lanes4::fromScalars([&](std::size_t j) { return c[j].z; });
  };
  pointLightSumsWith<Lanes4>(plain, lights.size(), p, attenuate);
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

Shader::Shader(const RenderScene& scene, const RenderSettings& settings, float pixelSpread)
    : rs_(scene),
      scene_(*scene.scene),
      settings_(settings),
      whitted_(settings.mode == RenderMode::Whitted),
      pixelSpread_(pixelSpread) {
  highlightLimits_.reserve(scene.materials.size());
  for (const Material& m : scene.materials) highlightLimits_.push_back(highlightLimits(m));
  rangeIndex_.resize(scene.instanceMaterialRanges.size());
  for (std::size_t i = 0; i < rangeIndex_.size(); ++i)
    if (!scene.instanceMaterialRanges[i].empty())
      rangeIndex_[i] = MaterialRangeIndex(scene.instanceMaterialRanges[i]);
  // Unused lanes of the last group repeat a light (groupLights); their terms are never read.
  const std::vector<PointLight>& lights = scene.pointLights;
  // Eight lights per pass where the packet kernels use AVX2 or wider, for more than four lights
  // and none attenuated (only the four-light terms attenuate): the same terms in fewer passes.
  const bool attenuated = std::any_of(lights.begin(), lights.end(),
                                      [](const PointLight& l) { return !l.attenuation.none(); });
  if (activeSimdIsa() != SimdIsa::Portable && lights.size() > 4 && !attenuated)
    pointTerms8_ = pointLightTermsAvx2();
  if (pointTerms8_ != nullptr) {
    groupLights(lights, pointGroups8_);
    pointSums8_ = pointLightSumsAvx2();
  } else {
    groupLights(lights, pointGroups4_);
  }
  plainLights_.reserve(lights.size());
  for (const PointLight& l : lights)
    plainLights_.push_back(
        {{l.position.x, l.position.y, l.position.z}, {l.color.x, l.color.y, l.color.z}});
}

template <typename Fn>
void Shader::forEachPointLightGroup(const SurfaceShading& sh, Fn&& fn) const {
  const LightTermsPoint p = lightTermsPoint(sh);
  const std::vector<PointLight>& points = rs_.pointLights;
  if (pointTerms8_ != nullptr) {
    for (std::size_t first = 0; first < points.size(); first += 8) {
      LightGroupTerms<8> t;
      pointTerms8_(pointGroups8_[first / 8], std::min<std::size_t>(8, points.size() - first), p, t);
      fn(first, t.present, t.added, t.rgb);
    }
    return;
  }
  for (std::size_t first = 0; first < points.size(); first += 4) {
    LightGroupTerms<4> t;
    pointLightTerms4(pointGroups4_[first / 4], points.data() + first,
                     std::min<std::size_t>(4, points.size() - first), p, t);
    fn(first, t.present, t.added, t.rgb);
  }
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
  s.color =
      debugMode ? debugColor(ray, hit, sd) : shadeHit(ray, hit, sd, 0, 1.0f, 0.0f, ctx, counters);
  return s;
}

void Shader::shadeOpenGlTile(const Ray* rays, const Hit* hits, std::size_t n,
                             TileCounters& counters, PixelSample* out) const {
  if (pointSums8_ != nullptr) {
    shadeOpenGlLanes<8>(rays, hits, n, counters, out, [&](SurfacePointLanes<8>& p) {
      pointSums8_(plainLights_.data(), plainLights_.size(), p);
    });
  } else {
    shadeOpenGlLanes<4>(rays, hits, n, counters, out, [&](SurfacePointLanes<4>& p) {
      pointLightSums4(rs_.pointLights, plainLights_.data(), p);
    });
  }
}

template <std::size_t W, typename Sums>
void Shader::shadeOpenGlLanes(const Ray* rays, const Hit* hits, std::size_t n,
                              TileCounters& counters, PixelSample* out, Sums&& sums) const {
  const bool otherLights = !rs_.directionalLights.empty() || !rs_.spotLights.empty();
  counters.traced.primary += n;
  // Lanes without a hit keep what an earlier pixel left: they add no light (their bit of `lit`
  // is clear) and nobody reads them. Zeroed once, not per group of W.
  SurfacePointLanes<W> lanes{};
  // Two passes per group of W pixels: the surfaces and materials of its hits, each asking for
  // its texels, then the shading that reads them. Texture lookups miss the cache on most hits
  // (the BART kitchen's textures hold several megabytes of texels): made one after the other,
  // their misses did not overlap. The first pass runs a group ahead of the second, so that the
  // texels asked for have a whole group's shading to arrive in: kitchen `opengl` frames 0.8%
  // faster (median of seven runs' median ratios, both ways alternated frame by frame in one
  // process), and without the hint at all they took 4.5% longer.
  struct Group {
    std::array<Scene::SurfaceData, W> sds;
    std::array<std::uint32_t, W> materialIndex;
    unsigned shaded = 0;
  };
  Group groups[2];
  std::array<std::optional<SurfaceShading>, W> shading;  // kept for the other lights only
  const auto surfaces = [&](Group& g, std::size_t first) {
    const std::size_t count = std::min(W, n - first);
    g.shaded = 0;
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t k = first + j;
      PixelSample& s = *::new (static_cast<void*>(&out[k])) PixelSample();
      if (!hits[k].valid()) {
        s.color = rs_.background;
        continue;
      }
      s.depth = hits[k].t;
      s.instanceId = hits[k].instanceId;
      s.primId = hits[k].primId;
      // Made in place: a returned value copied in was read back before its stores completed.
      const Scene::SurfaceData& sd = *::new (static_cast<void*>(&g.sds[j]))
                                         Scene::SurfaceData(scene_.surfaceAt(rays[k], hits[k]));
      s.normal = sd.shadingNormal;
      g.materialIndex[j] = materialIndexOf(hits[k]);
      prefetchTexels(g.materialIndex[j], sd);
      g.shaded |= 1u << j;
    }
  };
  if (n > 0) surfaces(groups[0], 0);
  for (std::size_t first = 0, at = 0; first < n; first += W, at ^= 1u) {
    if (first + W < n) surfaces(groups[at ^ 1u], first + W);
    Group& g = groups[at];
    lanes.lit = 0;
    lanes.reflective = 0;
    for (unsigned left = g.shaded; left != 0; left &= left - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(left));
      const std::size_t k = first + j;
      if (otherLights)
        setLane(lanes, j,
                shading[j].emplace(prepare(rays[k], hits[k], g.sds[j], 0.0f, g.materialIndex[j])));
      else
        setLane(lanes, j, prepare(rays[k], hits[k], g.sds[j], 0.0f, g.materialIndex[j]));
    }
    if (g.shaded != 0) {
      sums(lanes);
      for (unsigned left = g.shaded; left != 0; left &= left - 1) {
        const auto j = static_cast<std::size_t>(std::countr_zero(left));
        Vec3f color{lanes.color[0][j], lanes.color[1][j], lanes.color[2][j]};
        if (otherLights)
          forEachOtherLight(rs_, g.sds[j].position, [&](const LightSample& light, std::size_t) {
            if (const std::optional<Vec3f> local = otherLightTerm(*shading[j], light))
              color += *local;
          });
        out[first + j].color = color;
      }
    }
  }
}

Vec3f Shader::trace(const Ray& ray, int depth, float weight, float cone, TraversalContext& ctx,
                    TileCounters& counters) const {
  Hit hit;
  if (!scene_.intersect(ray, hit, ctx)) return rs_.background;
  return shadeHit(ray, hit, scene_.surfaceAt(ray, hit), depth, weight, cone, ctx, counters);
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

float Shader::textureLod(const SurfaceShading& sh, const Texture& texture) const {
  // The ray's cone is w = sh.coneWidth wide at the hit and covers w * w / |cos| of the
  // surface. The level chosen matches the square root of that area in texels (texels per area:
  // uv area per world area times texels per uv area), less half a level, since a bilinear
  // lookup spreads over about two texels of its level. PSNR against 4 x 4 supersampled frames
  // (640x480, frame 300, opengl), kitchen and robots: sized by the footprint's long side
  // w / |cos| (OpenGL's isotropic choice) 28.97 and 22.13 dB, by its area 31.39 and 22.42 dB,
  // with the half level 32.35 and 22.81 dB (bilinear: 29.65 and 17.00).
  const float cosine = std::abs(dot(sh.sd.geometricNormal, sh.dir));
  const float width = sh.coneWidth;
  const float texelsPerArea = scene_.uvAreaPerWorldArea(sh.hit) *
                              static_cast<float>(texture.width()) *
                              static_cast<float>(texture.height());
  return 0.5f * roughLog2(width * width * texelsPerArea / (2.0f * cosine));
}

std::uint32_t Shader::materialIndexOf(const Hit& hit) const {
  // RenderScene::material, keeping the index for the material's highlight cutoff.
  return rs_.materialIndexWith(hit.instanceId, hit.objectId, hit.primId,
                               [&](const MaterialRangeIndex::Ranges& ranges, std::uint32_t primId) {
                                 return rangeIndex_[hit.instanceId].find(ranges, primId);
                               });
}

void Shader::prefetchTexels(std::uint32_t materialIndex, const Scene::SurfaceData& sd) const {
  // Trilinear lookups read the mip levels, which the hint does not cover.
  if (settings_.textureFilter == TextureFilter::Trilinear) return;
  if (materialIndex >= rs_.materials.size() || !sd.hasUv) return;
  const std::uint32_t texture = rs_.materials[materialIndex].texture;
  if (texture != kInvalidId) rs_.textures[texture]->prefetch(sd.uv);
}

SurfaceShading Shader::prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd,
                               float cone) const {
  return prepare(ray, hit, sd, cone, materialIndexOf(hit));
}

SurfaceShading Shader::prepare(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd,
                               float cone, std::uint32_t index) const {
  const bool listed = index < rs_.materials.size();
  SurfaceShading sh{ray, hit, sd, listed ? rs_.materials[index] : defaultMaterial_};
  sh.highlight = listed ? highlightLimits_[index] : highlightLimits(defaultMaterial_);
  // Shade with the normals facing the incoming ray; the geometric normal alone decides the
  // side, because interpolated normals can disagree with it near silhouettes.
  sh.backFace = dot(sd.geometricNormal, ray.direction) > 0.0f;
  sh.ng = sh.backFace ? -sd.geometricNormal : sd.geometricNormal;
  sh.ns = sh.backFace ? -sd.shadingNormal : sd.shadingNormal;
  // normalize() divides by this length; the cone below needs it too.
  const float directionLength = length(ray.direction);
  sh.dir = ray.direction / directionLength;
  sh.v = -sh.dir;
  const bool mipMapped = settings_.textureFilter == TextureFilter::Trilinear;
  // The cone starts `cone` wide (a primary ray's at the eye: 0) and spreads by one pixel's
  // angle: reflection and refraction keep the spread, as a flat surface would (Ray Tracing
  // Gems' cones add the surface's curvature; flat is what BART's polygons are).
  if (mipMapped) sh.coneWidth = cone + hit.t * directionLength * pixelSpread_;
  const Material& m = sh.material;
  sh.diffuse = m.diffuse;
  Vec3f ambient = m.ambient;
  if (m.texture != kInvalidId && sd.hasUv) {
    const Texture& texture = *rs_.textures[m.texture];
    const Vec3f texel =
        mipMapped ? texture.sample(sd.uv, settings_.textureFilter, textureLod(sh, texture))
                  : texture.sample(sd.uv, settings_.textureFilter);
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
  // Fills the term of light `index`, which adds `local`, and passes it on. Filled in place: a
  // term built aside and then copied cost more than the Phong terms (partial stores read back
  // as one wide load stall the copy).
  auto add = [&](const Vec3f& local, std::size_t index, bool atInfinity, const Vec3f& direction,
                 const Vec3f& position) {
    LightTerm& term = slot(index);
    term.local = local;
    term.contributes = true;
    term.needsShadowRay = false;
    if (whitted_) {
      // Written in place (see spawnRay): a returned ray copied in here stalled on its stores.
      const SurfacePoint& sp = surface(sh);
      if (atInfinity) {
        spawnRay(sp, direction, term.shadow);
      } else {
        // spawnRayTo(sp, position, term.shadow), its origin made once per side of the surface
        // and shared by the lights on that side.
        const Vec3f w = position - sp.position;
        const unsigned side = leavesBelow(sp, w) ? 1u : 0u;
        if (!(sh.spawnOriginsMade & (1u << side))) {
          sh.spawnOrigin[side] = offsetRayOrigin(sp, w);
          sh.spawnOriginsMade |= 1u << side;
        }
        spawnRayFrom(sh.spawnOrigin[side], position, term.shadow);
      }
      if (term.shadow.tfar > 0.0f) {
        ++counters.traced.shadow;
        term.needsShadowRay = true;
      }
    }
    fn(term, index);
  };
  // Model only what the scene needs: no shadow ray when the light cannot change the colour.
  const std::vector<PointLight>& points = rs_.pointLights;
  forEachPointLightGroup(sh, [&](std::size_t first, unsigned present, unsigned added,
                                 const float(*rgb)[4]) {
    // A light exactly at the point lights nothing and saves nothing; present ones that add
    // nothing save their shadow ray. Then the adding ones, in light order.
    if (whitted_) counters.saved.shadow += std::popcount(present & ~added);
    for (unsigned lanes = added; lanes != 0; lanes &= lanes - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(lanes));
      add(Vec3f{rgb[j][0], rgb[j][1], rgb[j][2]}, first + j, false, {}, points[first + j].position);
    }
  });
  forEachOtherLight(rs_, sh.sd.position, [&](const LightSample& light, std::size_t index) {
    const std::optional<Vec3f> local = otherLightTerm(sh, light);
    if (!local) {
      if (whitted_) ++counters.saved.shadow;
      return;
    }
    add(*local, index, light.atInfinity, light.direction, light.position);
  });
}

Vec3f Shader::unshadowedColor(const SurfaceShading& sh) const {
  // forEachLightTerm's terms summed in the same order, without its slots and callbacks: the
  // sum then stays in registers (through the callbacks it went to memory once per light).
  Vec3f color = sh.color;
  forEachPointLightGroup(sh, [&](std::size_t, unsigned, unsigned added, const float(*rgb)[4]) {
    for (unsigned lanes = added; lanes != 0; lanes &= lanes - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(lanes));
      color += Vec3f{rgb[j][0], rgb[j][1], rgb[j][2]};
    }
  });
  if (!rs_.directionalLights.empty() || !rs_.spotLights.empty())
    forEachOtherLight(rs_, sh.sd.position, [&](const LightSample& light, std::size_t) {
      if (const std::optional<Vec3f> local = otherLightTerm(sh, light)) color += *local;
    });
  return color;
}

Vec3f Shader::shadeHit(const Ray& ray, const Hit& hit, const Scene::SurfaceData& sd, int depth,
                       float weight, float cone, TraversalContext& ctx,
                       TileCounters& counters) const {
  SurfaceShading sh = prepare(ray, hit, sd, cone);
  if (!whitted_) return unshadowedColor(sh);
  LightTerm term;
  forEachLightTerm(
      sh, counters, [&](std::size_t) -> LightTerm& { return term; },
      [&](const LightTerm& t, std::size_t) {
        if (t.needsShadowRay && scene_.occluded(t.shadow, ctx)) return;
        sh.color += t.local;
      });
  return addSecondary(sh, depth, weight, ctx, counters);
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
  const Vec3f reflected = s.reflects ? trace(s.reflection, depth + 1, s.reflectionPathWeight,
                                             sh.coneWidth, ctx, counters)
                                     : Vec3f{};
  const Vec3f refracted = s.refracts ? trace(s.refraction, depth + 1, s.refractionPathWeight,
                                             sh.coneWidth, ctx, counters)
                                     : Vec3f{};
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
