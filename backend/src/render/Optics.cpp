#include "tracegraph/backend/render/Optics.h"

#include <algorithm>
#include <cmath>

namespace tg {
namespace {

struct Coefficients {
  double reflectance = 1.0, transmittance = 0.0;
  double cosT = 0.0;
  bool tir = true;
};

/// Fresnel equations for s- and p-polarised light, averaged (unpolarised light).
Coefficients fresnel(double cosI, double n1, double n2) {
  Coefficients c;
  cosI = std::clamp(cosI, 0.0, 1.0);
  const double sin2T = (n1 / n2) * (n1 / n2) * (1.0 - cosI * cosI);
  if (sin2T >= 1.0 || cosI == 0.0) return c;  // beyond the critical angle, or exactly grazing
  c.tir = false;
  c.cosT = std::sqrt(1.0 - sin2T);
  const double a = n1 * cosI, b = n2 * c.cosT;  // s-polarisation terms
  const double p = n2 * cosI, q = n1 * c.cosT;  // p-polarisation terms
  const double rs = (a - b) / (a + b), rp = (p - q) / (p + q);
  const double ts = 2.0 * a / (a + b), tp = 2.0 * a / (p + q);
  c.reflectance = 0.5 * (rs * rs + rp * rp);
  // Transmitted power also scales with the beam's cross-section (cosT / cosI) and the
  // impedance of the second medium (n2 / n1).
  c.transmittance = 0.5 * (ts * ts + tp * tp) * (n2 * c.cosT) / (n1 * cosI);
  return c;
}

}  // namespace

Vec3f reflect(const Vec3f& d, const Vec3f& n) {
  return d - n * (2.0f * dot(d, n));
}

FresnelSplit fresnelRefract(const Vec3f& d, const Vec3f& n, float etaI, float etaT) {
  const Vec3d dd = normalize(Vec3d(d));
  const Vec3d nd(n);
  const double cosI = -dot(dd, nd);
  const Coefficients c = fresnel(cosI, etaI, etaT);
  FresnelSplit out;
  out.reflectance = static_cast<float>(c.reflectance);
  out.transmittance = static_cast<float>(c.transmittance);
  out.totalInternalReflection = c.tir;
  if (!c.tir) {
    // Snell's law in vector form: t = eta d + (eta cosI - cosT) n.
    const double eta = static_cast<double>(etaI) / static_cast<double>(etaT);
    const Vec3d t = dd * eta + nd * (eta * std::clamp(cosI, 0.0, 1.0) - c.cosT);
    out.refracted = Vec3f(normalize(t));
  }
  return out;
}

float fresnelReflectance(float cosI, float etaI, float etaT) {
  return static_cast<float>(fresnel(cosI, etaI, etaT).reflectance);
}

}  // namespace tg
