#include "RayGenerators.h"

#include "ToolArgs.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <system_error>

namespace tg::bench {

bool parseImageSize(const std::string& text, ImageSize& size) {
  std::uint32_t w = 0, h = 0;
  if (!tools::parseImageSizeArgument(text, w, h)) return false;
  size = {static_cast<int>(w), static_cast<int>(h)};
  return true;
}

PinholeCamera frameBounds(const Box3f& bounds, ImageSize size) {
  const Box3d b(Vec3d(bounds.lower), Vec3d(bounds.upper));
  const Vec3d centre = b.center();
  const double radius = std::max(0.5 * length(b.extent()), 1e-6);
  const double halfFov = 20.0 * std::numbers::pi / 180.0;
  const Vec3d toEye = normalize(Vec3d(1.0, 0.75, 1.25));
  PinholeCamera cam;
  cam.eye = centre + toEye * (radius / std::sin(halfFov));
  cam.forward = -toEye;
  const Vec3d right = normalize(cross(cam.forward, Vec3d(0, 1, 0)));
  const Vec3d up = cross(right, cam.forward);
  const double aspect = static_cast<double>(size.width) / size.height;
  cam.right = right * (std::tan(halfFov) * aspect);
  cam.up = up * std::tan(halfFov);
  return cam;
}

std::vector<Ray> makePrimaryRays(const PinholeCamera& camera, ImageSize size) {
  std::vector<Ray> rays(size.pixels());
  const Vec3f eye(camera.eye);
  for (int y = 0; y < size.height; ++y) {
    const double sy = 1.0 - 2.0 * (y + 0.5) / size.height;
    for (int x = 0; x < size.width; ++x) {
      const double sx = 2.0 * (x + 0.5) / size.width - 1.0;
      Ray& ray = rays[static_cast<std::size_t>(y) * size.width + x];
      ray.origin = eye;
      ray.direction = Vec3f(normalize(camera.forward + camera.right * sx + camera.up * sy));
      ray.tnear = 0.0f;
      ray.tfar = kInfinity;
    }
  }
  return rays;
}

std::vector<Ray> makePrimaryRays(const CameraParams& params, ImageSize size) {
  CameraParams p = params;
  p.width = static_cast<std::uint32_t>(size.width);
  p.height = static_cast<std::uint32_t>(size.height);
  const Camera camera(p);
  std::vector<Ray> rays(size.pixels());
  for (std::uint32_t y = 0; y < p.height; ++y)
    for (std::uint32_t x = 0; x < p.width; ++x)
      rays[static_cast<std::size_t>(y) * p.width + x] = camera.primaryRay(x, y);
  return rays;
}

Vec3f lightAbove(const Box3f& bounds) {
  const Vec3f centre = bounds.center();
  const float radius = 0.5f * length(bounds.extent());
  return {centre.x + 0.3f * radius, bounds.upper.y + 1.5f * radius, centre.z + 0.2f * radius};
}

std::vector<Ray> makeShadowRays(std::span<const Ray> primary, std::span<const SurfaceHit> hits,
                                const Vec3f& light, float offset) {
  std::vector<Ray> rays;
  for (std::size_t i = 0; i < primary.size() && i < hits.size(); ++i) {
    if (!(hits[i].t < kInfinity)) continue;
    const Ray& p = primary[i];
    Vec3f n = hits[i].normal;
    if (dot(n, p.direction) > 0.0f) n = -n;
    Ray ray;
    ray.origin = p.origin + p.direction * hits[i].t + n * offset;
    ray.direction = light - ray.origin;
    ray.tnear = 0.0f;
    ray.tfar = 1.0f;
    rays.push_back(ray);
  }
  return rays;
}

}  // namespace tg::bench
