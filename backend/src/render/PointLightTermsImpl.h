// The Phong terms of a group of point lights at one surface point, written once for any lane
// width: Shading.cpp instantiates it with four SSE lanes (or a portable fallback), and
// LightTermsAvx2.cpp with eight AVX lanes. Each translation unit gets its own copy (internal
// linkage, see LightTerms.h). Internal header: not installed.
#pragma once

#include "LightTerms.h"

namespace tg::detail {
namespace {

/// What the single-light shading computes for one point light (direction, attenuation, the
/// tests that skip it, Phong, the black test of the result), for the `count` lights of group
/// `q` at point `p` at once, in the same IEEE operations lane by lane: identical terms, in a
/// fraction of the instructions. `L` is a lane type of L::kWidth floats with the operations
/// below; attenuate(distance, r, g, b) replaces the lights' colours when q.attenuated.
template <class L, class Attenuate>
void pointLightTermsWith(const PointLightGroup<L::kWidth>& q, std::size_t count,
                         const LightTermsPoint& p, const Attenuate& attenuate,
                         LightGroupTerms<L::kWidth>& out) {
  const L zero = L::splat(0.0f);
  const L tx = L::load(q.x) - L::splat(p.position[0]);
  const L ty = L::load(q.y) - L::splat(p.position[1]);
  const L tz = L::load(q.z) - L::splat(p.position[2]);
  const L distance = sqrt(tx * tx + ty * ty + tz * tz);  // length(toLight)
  const L dx = tx / distance, dy = ty / distance, dz = tz / distance;
  const auto dotDirection = [&](const float* n) {
    return L::splat(n[0]) * dx + L::splat(n[1]) * dy + L::splat(n[2]) * dz;
  };
  const L nl = dotDirection(p.ns), ngl = dotDirection(p.ng);
  L cr = L::load(q.r), cg = L::load(q.g), cb = L::load(q.b);
  if (q.attenuated) attenuate(distance, cr, cg, cb);
  // Lanes past `count` and lanes that fail a test compute garbage that no one reads.
  const auto present = distance > zero;
  const auto lightNotBlack = (cr > zero) | (cg > zero) | (cb > zero);
  const auto facing =
      andNot(present & lightNotBlack & L::allLanes(p.lit), (nl <= zero) | (ngl <= zero));
  // phong(): diffuse * nl, plus the highlight where r.v > 0 and r.v >= the cutoff.
  L r = L::splat(p.diffuse[0]) * nl, g = L::splat(p.diffuse[1]) * nl,
    b = L::splat(p.diffuse[2]) * nl;
  const unsigned used = (1u << count) - 1u;
  if (p.reflective) {
    const L twoNl = L::splat(2.0f) * nl;
    const L rx = L::splat(p.ns[0]) * twoNl - dx, ry = L::splat(p.ns[1]) * twoNl - dy,
            rz = L::splat(p.ns[2]) * twoNl - dz;
    const L rv = rx * L::splat(p.v[0]) + ry * L::splat(p.v[1]) + rz * L::splat(p.v[2]);
    const auto absorbed = (L::splat(p.negligibleBelow) > rv) & (r > zero) & (g > zero) &
                          (b > zero) & (r >= L::splat(p.absorbingDiffuse[0])) &
                          (g >= L::splat(p.absorbingDiffuse[1])) &
                          (b >= L::splat(p.absorbingDiffuse[2]));
    const auto highlight = andNot(facing & (rv > zero) & (rv >= L::splat(p.cutoff)), absorbed);
    if (const unsigned lanes = bits(highlight) & used) {
      alignas(32) float rvs[L::kWidth];
      L::store(rv, rvs);
      // powf itself (what std::pow of floats calls), not a wrapper inline in every unit.
      const L power = L::fromScalars(
          [&](unsigned j) { return (lanes >> j & 1u) ? __builtin_powf(rvs[j], p.shine) : 0.0f; });
      r = select(highlight, r + L::splat(p.specular[0]) * power, r);
      g = select(highlight, g + L::splat(p.specular[1]) * power, g);
      b = select(highlight, b + L::splat(p.specular[2]) * power, b);
    }
  }
  r = cr * r;
  g = cg * g;
  b = cb * b;
  const auto added = facing & ((r > zero) | (g > zero) | (b > zero));
  storeColors(r, g, b, out.rgb);
  out.present = bits(present) & used;
  out.added = bits(added) & used;
}

/// pointLightTermsWith turned around: the lanes are L::kWidth surface points and the loop runs
/// over the lights, adding each light's term where it adds a non-black one, as the per-point
/// sum over LightGroupTerms does. Every lane computes what pointLightTermsWith computes for its
/// point and the light, operation for operation, so the sums are the same bits.
/// attenuate(light, distance, r, g, b) replaces light `light`'s colour when it is attenuated.
template <class L, class Attenuate>
void pointLightSumsWith(const PlainPointLight* lights, std::size_t count,
                        SurfacePointLanes<L::kWidth>& p, const Attenuate& attenuate) {
  const L zero = L::splat(0.0f);
  const auto row = [](const float* r) { return L::load(r); };
  const L px = row(p.position[0]), py = row(p.position[1]), pz = row(p.position[2]);
  const L nsx = row(p.ns[0]), nsy = row(p.ns[1]), nsz = row(p.ns[2]);
  const L ngx = row(p.ng[0]), ngy = row(p.ng[1]), ngz = row(p.ng[2]);
  const auto lit = L::fromBits(p.lit);
  const auto reflective = L::fromBits(p.reflective);
  L red = row(p.color[0]), green = row(p.color[1]), blue = row(p.color[2]);
  for (std::size_t i = 0; i < count; ++i) {
    const PlainPointLight& light = lights[i];
    const L tx = L::splat(light.position[0]) - px;
    const L ty = L::splat(light.position[1]) - py;
    const L tz = L::splat(light.position[2]) - pz;
    const L distance = sqrt(tx * tx + ty * ty + tz * tz);
    const L dx = tx / distance, dy = ty / distance, dz = tz / distance;
    // The normals' coordinates multiply from the left, as in pointLightTermsWith.
    const L nl = nsx * dx + nsy * dy + nsz * dz, ngl = ngx * dx + ngy * dy + ngz * dz;
    L cr = L::splat(light.color[0]), cg = L::splat(light.color[1]), cb = L::splat(light.color[2]);
    attenuate(i, distance, cr, cg, cb);
    const auto present = distance > zero;
    const auto lightNotBlack = (cr > zero) | (cg > zero) | (cb > zero);
    const auto facing = andNot(present & lightNotBlack & lit, (nl <= zero) | (ngl <= zero));
    if (bits(facing) == 0) continue;  // no lane adds this light
    L r = row(p.diffuse[0]) * nl, g = row(p.diffuse[1]) * nl, b = row(p.diffuse[2]) * nl;
    if (bits(facing & reflective) != 0) {
      const L twoNl = L::splat(2.0f) * nl;
      const L rx = nsx * twoNl - dx, ry = nsy * twoNl - dy, rz = nsz * twoNl - dz;
      const L rv = rx * row(p.v[0]) + ry * row(p.v[1]) + rz * row(p.v[2]);
      const auto absorbed = (row(p.negligibleBelow) > rv) & (r > zero) & (g > zero) & (b > zero) &
                            (r >= row(p.absorbingDiffuse[0])) & (g >= row(p.absorbingDiffuse[1])) &
                            (b >= row(p.absorbingDiffuse[2]));
      const auto highlight =
          andNot(facing & reflective & (rv > zero) & (rv >= row(p.cutoff)), absorbed);
      if (const unsigned lanes = bits(highlight)) {
        alignas(64) float rvs[L::kWidth];
        L::store(rv, rvs);
        const L power = L::fromScalars([&](unsigned j) {
          return (lanes >> j & 1u) ? __builtin_powf(rvs[j], p.shine[j]) : 0.0f;
        });
        r = select(highlight, r + row(p.specular[0]) * power, r);
        g = select(highlight, g + row(p.specular[1]) * power, g);
        b = select(highlight, b + row(p.specular[2]) * power, b);
      }
    }
    r = cr * r;
    g = cg * g;
    b = cb * b;
    const auto added = facing & ((r > zero) | (g > zero) | (b > zero));
    red = select(added, red + r, red);
    green = select(added, green + g, green);
    blue = select(added, blue + b, blue);
  }
  L::store(red, p.color[0]);
  L::store(green, p.color[1]);
  L::store(blue, p.color[2]);
}

}  // namespace
}  // namespace tg::detail
