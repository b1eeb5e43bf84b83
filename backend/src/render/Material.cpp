#include "tracegraph/backend/render/Material.h"

#include <cmath>

namespace tg {
namespace {

bool isNonNegativeColor(const Vec3f& c) {
  return isFinite(c) && c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f;
}

}  // namespace

Material Material::fromNff(const Vec3f& rgb, float kd, float ks, float shine, float t, float ior) {
  Material m;
  m.ambient = {0.0f, 0.0f, 0.0f};
  m.diffuse = rgb * kd;
  m.specular = {ks, ks, ks};
  m.shine = shine;
  m.transmittance = t;
  m.ior = ior;
  return m;
}

std::string Material::validate() const {
  if (!isNonNegativeColor(ambient)) return "ambient colour is negative, NaN or infinite";
  if (!isNonNegativeColor(diffuse)) return "diffuse colour is negative, NaN or infinite";
  if (!isNonNegativeColor(specular)) return "specular colour is negative, NaN or infinite";
  if (!(shine >= 0.0f) || !std::isfinite(shine)) return "shine is negative, NaN or infinite";
  if (!(transmittance >= 0.0f && transmittance <= 1.0f)) return "transmittance is not in [0, 1]";
  if (!(ior >= 0.0f) || !std::isfinite(ior)) return "index of refraction is negative or NaN";
  return {};
}

}  // namespace tg
