/// @file Renderer.h
/// The tile-parallel ray-tracing renderer: shading modes, AOVs and per-frame statistics.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "tracegraph/backend/render/Camera.h"
#include "tracegraph/backend/render/Image.h"
#include "tracegraph/backend/render/RenderScene.h"
#include "tracegraph/backend/render/RenderStats.h"
#include "tracegraph/backend/render/Texture.h"

namespace tg {

/// What the renderer computes per pixel.
enum class RenderMode : std::uint8_t {
  OpenGL,     ///< primary rays and local Phong with ambient, no shadows (the OpenGL look)
  Whitted,    ///< + shadow rays, mirror reflection, Fresnel refraction (Whitted 1980)
  Normals,    ///< world shading normal as colour, 0.5 (n + 1)
  Classes,    ///< colour by dynamics class: static grey-blue, rigid green, deforming orange
  Instances,  ///< a hash colour per instance id
};

/// "opengl", "whitted", "normals", "classes", "instances".
std::string_view renderModeName(RenderMode mode);
/// The mode named `name` (as renderModeName spells it), or nothing.
std::optional<RenderMode> parseRenderMode(std::string_view name);

/// Renderer options.
struct RenderSettings {
  /// What each pixel shows.
  RenderMode mode = RenderMode::Whitted;
  /// Reflection/refraction bounces allowed after the primary hit (Whitted mode).
  int maxDepth = 5;
  /// A secondary ray whose weight (product of the reflectances along its path, largest RGB
  /// component) would fall below this is not traced.
  float minWeight = 0.01f;
  /// Tile edge in pixels; tiles are the unit of parallel work.
  std::uint32_t tileSize = 16;
  /// How textures are sampled. Trilinear mip-maps by the footprint of each ray's cone (one
  /// pixel wide at the camera, widening on through reflections and refractions): less aliasing
  /// where textures are minified, at some cost per lookup.
  TextureFilter textureFilter = TextureFilter::Bilinear;
  /// Fill the AOVs (depth, normal, instance and primitive ids); off saves memory and time.
  bool aovs = true;
  /// Flush denormals to zero while tracing (FTZ/DAZ on x86). Denormals arise in grazing
  /// Fresnel terms and high Phong exponents and are slow on many CPUs; flushing changes no
  /// visible colour. Every tile sets the mode itself, so images stay identical on any thread.
  bool flushDenormals = true;
  /// Trace primary rays as packets of 4 x 2 pixels (Scene::intersect over spans). The hits,
  /// and so the images, are identical either way; off traces every primary ray alone.
  bool packets = true;
};

/// The images of one frame. render() allocates them when their size differs from the camera's
/// and otherwise overwrites every pixel in place.
struct Frame {
  Image beauty;        ///< linear RGB
  Image depth;         ///< 1 channel: distance along the unit primary ray, +inf on a miss
  Image normal;        ///< 3 channels: world shading normal of the primary hit (not flipped
                       ///< towards the viewer), 0 on a miss
  IdImage instanceId;  ///< instance of the primary hit, kInvalidId on a miss
  IdImage primId;      ///< triangle of the primary hit, kInvalidId on a miss
};

/// Renders frames of a RenderScene through a Camera.
///
/// Work is split into square tiles traced in parallel with oneTBB in the calling thread's task
/// arena (wrap the call in a tbb::task_arena to choose the thread count). Every pixel is
/// computed independently from its own rays, and statistics are integer counts summed after
/// the parallel loop, so images, AOVs and counts are bit-identical for any number of threads.
class Renderer {
 public:
  /// A renderer with the given settings.
  explicit Renderer(const RenderSettings& settings = {}) : settings_(settings) {}

  /// The settings used by render().
  const RenderSettings& settings() const { return settings_; }
  /// Replaces the settings (not during a render() on another thread).
  void setSettings(const RenderSettings& settings) { settings_ = settings; }

  /// Renders one frame into `frame`. The scene must be committed and must not be edited during
  /// the call. Throws tg::Error when `scene.validate()` reports a problem or the settings are
  /// invalid (tile size 0, negative depth, NaN cutoff).
  RenderStats render(const RenderScene& scene, const Camera& camera, Frame& frame) const;

 private:
  RenderSettings settings_;
};

}  // namespace tg
