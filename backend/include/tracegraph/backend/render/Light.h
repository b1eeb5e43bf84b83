/// @file Light.h
/// Light sources of the Whitted and OpenGL-like shading modes.
///
/// All lights are ideal (points or directions), so shadows are hard and one shadow ray per light
/// decides visibility. Colours are linear RGB and already include any intensity factor.
#pragma once

#include <algorithm>
#include <cmath>

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Distance attenuation 1 / max(c0 + c1 d + c2 d^2, 1), as X3D and OpenGL define it. The default
/// (1, 0, 0) means no attenuation, which is what NFF and BART (AFF) point lights use.
struct LightAttenuation {
  float constant = 1.0f;   ///< c0
  float linear = 0.0f;     ///< c1
  float quadratic = 0.0f;  ///< c2

  /// The factor at distance `d`.
  float factor(float d) const {
    const float denominator = constant + linear * d + quadratic * d * d;
    return 1.0f / std::max(denominator, 1.0f);
  }
  /// True for the default (1, 0, 0): the shader then skips the distance computation.
  bool none() const { return constant == 1.0f && linear == 0.0f && quadratic == 0.0f; }
};

/// A point light radiating equally in all directions (NFF/AFF `l`, X3D PointLight).
struct PointLight {
  Vec3f position;                 ///< world space
  Vec3f color{1.0f, 1.0f, 1.0f};  ///< linear RGB
  LightAttenuation attenuation;   ///< none by default, as in BART
};

/// A light infinitely far away (X3D DirectionalLight, a sun).
struct DirectionalLight {
  Vec3f direction{0.0f, -1.0f, 0.0f};  ///< direction the light travels; need not be unit
  Vec3f color{1.0f, 1.0f, 1.0f};       ///< linear RGB
};

/// A cone of light (X3D SpotLight). Full intensity within `beamWidth` of the axis, falling off
/// linearly in angle to zero at `cutOffAngle` (X3D's definition); nothing beyond it.
struct SpotLight {
  Vec3f position;                      ///< world space
  Vec3f direction{0.0f, -1.0f, 0.0f};  ///< cone axis, pointing away from the light
  Vec3f color{1.0f, 1.0f, 1.0f};       ///< linear RGB
  float cutOffAngle = 0.785398f;       ///< radians; no light beyond this angle (X3D default)
  float beamWidth = 1.570796f;         ///< radians; full light within this angle (X3D default)
  LightAttenuation attenuation;        ///< none by default

  /// Angular factor in [0, 1] for the unit vector `toPoint` from the light to the lit point.
  float coneFactor(const Vec3f& toPoint) const {
    const float cosAngle = dot(normalize(direction), toPoint);
    const float angle = std::acos(std::clamp(cosAngle, -1.0f, 1.0f));
    if (angle >= cutOffAngle) return 0.0f;
    if (angle <= beamWidth) return 1.0f;
    return (cutOffAngle - angle) / (cutOffAngle - beamWidth);
  }
};

}  // namespace tg
