/// @file Optics.h
/// Mirror reflection, refraction and the dielectric Fresnel equations used by Whitted shading.
#pragma once

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Mirror direction of `d` about the unit normal `n`: d - 2 (d.n) n (same length as d).
Vec3f reflect(const Vec3f& d, const Vec3f& n);

/// What happens to light arriving at a smooth boundary between two dielectrics.
struct FresnelSplit {
  /// Fraction of the energy reflected (1 under total internal reflection).
  float reflectance = 1.0f;
  /// Fraction transmitted, computed from the Fresnel *transmission* coefficients (scaled by
  /// the ratio of beam cross-sections and indices), not as 1 - reflectance, so that
  /// reflectance + transmittance = 1 is a check of the equations rather than a definition.
  float transmittance = 0.0f;
  /// True beyond the critical angle: no refracted ray exists.
  bool totalInternalReflection = false;
  /// Unit refracted direction (Snell's law); meaningless under total internal reflection.
  Vec3f refracted;
};

/// Unpolarised Fresnel split and refracted direction for a ray of direction `d` (any length)
/// arriving at a boundary with unit normal `n` on the incident side (d.n < 0), going from a
/// medium of index `etaI` into one of index `etaT`. Computed in double and rounded once, so a
/// ray through a parallel slab leaves with its direction unchanged to float precision.
FresnelSplit fresnelRefract(const Vec3f& d, const Vec3f& n, float etaI, float etaT);

/// Unpolarised Fresnel reflectance for cosI = cos(angle of incidence) in [0, 1]; 1 beyond the
/// critical angle.
float fresnelReflectance(float cosI, float etaI, float etaT);

}  // namespace tg
