// The point-light terms of one surface point as plain data, shared by the baseline shader and
// the wider light kernels (LightTermsAvx2.cpp). Only plain numbers and C arrays cross between
// them: a kernel compiled for another instruction set must not call inline functions that the
// baseline also compiles (the linker keeps one copy of each, which could then be the wider
// one, as in builds without inlining). Internal header: not installed.
#pragma once

#include <cstddef>

namespace tg::detail {

/// W point lights of a frame by coordinate, so that their terms at a surface point are computed
/// W at a time. Unused lanes of a frame's last group repeat a light; nobody reads their terms.
template <std::size_t W>
struct PointLightGroup {
  alignas(32) float x[W] = {}, y[W] = {}, z[W] = {};  ///< positions
  alignas(32) float r[W] = {}, g[W] = {}, b[W] = {};  ///< colours, before any attenuation
  bool attenuated = false;  ///< some light of the group has distance attenuation
};

/// A surface point as the light terms read it (see SurfaceShading and Material).
struct LightTermsPoint {
  float position[3];          ///< the hit point
  float ns[3], ng[3];         ///< shading and geometric normal, facing the incoming ray
  float v[3];                 ///< unit view vector
  float diffuse[3];           ///< diffuse colour after texturing
  float specular[3];          ///< Material::specular
  float shine;                ///< Material::shine
  bool lit;                   ///< Material::lit()
  bool reflective;            ///< Material::reflective()
  float cutoff;               ///< HighlightLimits::cutoff
  float negligibleBelow;      ///< HighlightLimits::negligibleBelow
  float absorbingDiffuse[3];  ///< HighlightLimits::absorbingDiffuse
};

/// The Phong terms of the lights of a group at one surface point.
template <std::size_t W>
struct LightGroupTerms {
  /// Per light: red, green, blue of its colour times the Phong terms (valid where added), and
  /// an unused fourth float. One light's colour lies in one 16-byte store, which the loads of
  /// its three channels can forward from; channel-major rows made the loads of the last light
  /// span two stores, and wait for both to reach the cache.
  alignas(16) float rgb[W][4];
  unsigned present = 0;  ///< bit j: light j is not exactly at the point
  unsigned added = 0;    ///< bit j: light j adds a non-black term (a subset of present)
};

/// One point light as plain numbers, for the sums over surface points (PointLightSums8Fn).
struct PlainPointLight {
  float position[3];
  float color[3];  ///< before any attenuation
};

/// W surface points, one per lane, as the sums over surface points read them: the fields of
/// LightTermsPoint by lane, and the colour each point has so far.
template <std::size_t W>
struct SurfacePointLanes {
  /// A vector per lane: row a holds coordinate (or channel) a of every lane.
  using Rows = float[3][W];
  alignas(32) Rows position;             ///< hit points
  alignas(32) Rows ns, ng;               ///< shading and geometric normals, facing the ray
  alignas(32) Rows v;                    ///< unit view vectors
  alignas(32) Rows diffuse;              ///< diffuse colours after texturing
  alignas(32) Rows specular;             ///< Material::specular
  alignas(32) Rows absorbingDiffuse;     ///< HighlightLimits::absorbingDiffuse
  alignas(32) float shine[W];            ///< Material::shine
  alignas(32) float cutoff[W];           ///< HighlightLimits::cutoff
  alignas(32) float negligibleBelow[W];  ///< HighlightLimits::negligibleBelow
  /// In: the colour so far (the ambient term); out: plus every point light's term.
  alignas(32) Rows color;
  unsigned lit = 0;         ///< bit j: the material of lane j is lit
  unsigned reflective = 0;  ///< bit j: the material of lane j is reflective
};

/// Adds to points.color every one of `count` point lights' unshadowed terms, light by light in
/// order, where a light adds a non-black term: for each lane, the colour OpenGL mode
/// sums through the light terms of LightTermsPoint, bit for bit. None of the lights attenuates.
using PointLightSums8Fn = void (*)(const PlainPointLight* lights, std::size_t count,
                                   SurfacePointLanes<8>& points);

/// The AVX2 kernel of PointLightSums8Fn, or null when the build has none. Call it only on a CPU
/// that runs AVX2.
PointLightSums8Fn pointLightSumsAvx2();

/// Terms of the first `count` lights of an 8-light group without attenuation at point `p`.
using PointLightTerms8Fn = void (*)(const PointLightGroup<8>& group, std::size_t count,
                                    const LightTermsPoint& p, LightGroupTerms<8>& out);

/// The AVX2 kernel of PointLightTerms8Fn, or null when the build has none. Call it only on a
/// CPU that runs AVX2. Its terms equal the baseline's four-light ones bit for bit: the same IEEE
/// operations lane by lane, without contraction.
PointLightTerms8Fn pointLightTermsAvx2();

}  // namespace tg::detail
