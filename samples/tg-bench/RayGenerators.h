/// @file RayGenerators.h
/// The rays of the trace suite: primary rays of a pinhole camera framing the scene and shadow
/// rays from their hit points to a point light. Generated once and shared by every
/// implementation, so that throughput and hit comparisons are over identical rays.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/render/Camera.h"

namespace tg::bench {

/// Image resolution in pixels.
struct ImageSize {
  int width = 1024;
  int height = 768;
  std::size_t pixels() const { return static_cast<std::size_t>(width) * height; }
};

/// Parses "WxH" (both positive, at most 16384); false on anything else.
bool parseImageSize(const std::string& text, ImageSize& size);

/// A pinhole camera: eye point and the world-space vectors spanning the image plane at unit
/// distance (pixel (x, y), y = 0 at the top, looks along forward + sx * right + sy * up with
/// sx, sy in [-1, 1]).
struct PinholeCamera {
  Vec3d eye;
  Vec3d forward;
  Vec3d right;  ///< scaled by tan(fov/2) * aspect
  Vec3d up;     ///< scaled by tan(fov/2)
};

/// A camera with a 40 degree vertical field of view looking at the centre of `bounds` from a
/// corner direction (+x, +y, +z side, y up), far enough back that the bounding sphere fits.
PinholeCamera frameBounds(const Box3f& bounds, ImageSize size);

/// One unit-direction ray through the centre of each pixel, row-major from the top row.
std::vector<Ray> makePrimaryRays(const PinholeCamera& camera, ImageSize size);
/// The renderer's primary rays (Camera::primaryRay) of `params` at `size`, row-major from the
/// top row: the rays a frame of the scene traces.
std::vector<Ray> makePrimaryRays(const CameraParams& params, ImageSize size);

/// A point light above the scene: over the centre (shifted a little so that shadows are not
/// symmetric), higher than the top of `bounds` by 1.5 bounding radii.
Vec3f lightAbove(const Box3f& bounds);

/// A primary hit needed to spawn a shadow ray.
struct SurfaceHit {
  float t = kInfinity;  ///< kInfinity: the primary ray missed
  Vec3f normal;         ///< world geometric normal (either side)
};

/// Shadow rays for every primary ray that hit: the origin is the hit point moved by `offset`
/// along the normal, to the side the primary ray came from (so the ray cannot re-hit its own
/// triangle); the direction is light - origin with t in [0, 1]. Misses spawn no ray.
std::vector<Ray> makeShadowRays(std::span<const Ray> primary, std::span<const SurfaceHit> hits,
                                const Vec3f& light, float offset);

}  // namespace tg::bench
