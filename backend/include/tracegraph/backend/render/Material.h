/// @file Material.h
/// The NFF/BART Phong material (aff-format.md section 5).
#pragma once

#include <cstdint>
#include <string>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// How a material's texture combines with its colours.
enum class TextureMode : std::uint8_t {
  Modulate,  ///< ambient and diffuse are multiplied by the texel (OpenGL GL_MODULATE)
  Replace,   ///< the texel becomes the diffuse colour; ambient is multiplied by it
};

/// A Phong material as NFF `f` and AFF `fm` describe it. Shading (Whitted mode):
///
///   C = ambient (x) A + sum over lights of vis * Lc (x) (diffuse max(0, N.L) +
///       specular max(0, R.V)^shine) + specular (x) C_reflected + T * C_refracted,
///
/// where A is the scene's ambient light and, for T > 0, the transmitted part is split between
/// reflection and refraction by the dielectric Fresnel equations.
struct Material {
  Vec3f ambient{0.0f, 0.0f, 0.0f};     ///< reflectance for the scene's ambient light
  Vec3f diffuse{0.8f, 0.8f, 0.8f};     ///< Lambert reflectance
  Vec3f specular{0.0f, 0.0f, 0.0f};    ///< Phong highlight colour and mirror reflectance
  float shine = 0.0f;                  ///< Phong exponent on R.V
  float transmittance = 0.0f;          ///< T in [0, 1]; T > 0 makes the surface two-sided glass
  float ior = 1.0f;                    ///< index of refraction; 0 (as robots uses) means 1
  std::uint32_t texture = kInvalidId;  ///< index into RenderScene::textures, or kInvalidId
  TextureMode textureMode = TextureMode::Modulate;  ///< how the texture combines

  /// NFF `f r g b Kd Ks shine T ior`: diffuse = Kd * rgb, specular = Ks (white), no ambient.
  static Material fromNff(const Vec3f& rgb, float kd, float ks, float shine, float t, float ior);

  /// The index of refraction to use: ior, or 1 when ior is 0 (robots' glass has ior 0).
  float effectiveIor() const { return ior == 0.0f ? 1.0f : ior; }
  /// True when the material spawns mirror-reflection rays (any specular component > 0).
  bool reflective() const { return specular.x > 0.0f || specular.y > 0.0f || specular.z > 0.0f; }
  /// True when the material spawns refraction rays.
  bool transmissive() const { return transmittance > 0.0f; }
  /// True when direct light can change its colour (diffuse or specular non-zero).
  bool lit() const {
    return reflective() || diffuse.x > 0.0f || diffuse.y > 0.0f || diffuse.z > 0.0f;
  }

  /// Empty when usable, otherwise what is wrong: NaN/Inf or negative colours, negative shine,
  /// T outside [0, 1], negative ior.
  std::string validate() const;
};

}  // namespace tg
