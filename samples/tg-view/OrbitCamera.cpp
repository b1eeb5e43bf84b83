#include "OrbitCamera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tg::view_tool {
namespace {

// Keep the eye off the up axis: at the pole the view direction is parallel to up and the
// camera has no defined orientation.
constexpr double kMaxPitch = 0.49 * std::numbers::pi;

Vec3d unit(const Vec3d& v, const Vec3d& fallback) {
  const double len = length(v);
  return len > 1e-12 ? v / len : fallback;
}

}  // namespace

void OrbitCamera::takeOver(const Camera& current, const Box3f& sceneBounds) {
  const CameraParams& p = current.params();
  const Vec3d eye(p.eye);
  const Vec3d dir = unit(Vec3d(p.viewDirection), {0.0, 0.0, -1.0});
  up_ = unit(Vec3d(p.up), {0.0, 1.0, 0.0});
  double depth = 1.0;
  if (!sceneBounds.empty()) {
    const Vec3d centre(sceneBounds.center());
    const double extent = length(Vec3d(sceneBounds.extent()));
    depth = std::max(dot(centre - eye, dir), 0.05 * std::max(extent, 1e-3));
  }
  target_ = eye + dir * depth;
  distance_ = depth;
  // Spherical coordinates of the eye around the target in the frame (east, north, up).
  const Vec3d back = -dir;
  east_ = unit(back - up_ * dot(back, up_), unit(cross(up_, {1.0, 0.0, 0.0}), {0.0, 0.0, 1.0}));
  north_ = cross(up_, east_);
  yaw_ = 0.0;
  pitch_ = std::clamp(std::asin(std::clamp(dot(back, up_), -1.0, 1.0)), -kMaxPitch, kMaxPitch);
  fovY_ = p.fovYDegrees;
  hither_ = p.hither;
  active_ = true;
}

Vec3d OrbitCamera::eye() const {
  const Vec3d horizontal = east_ * std::cos(yaw_) + north_ * std::sin(yaw_);
  return target_ + (horizontal * std::cos(pitch_) + up_ * std::sin(pitch_)) * distance_;
}

void OrbitCamera::orbit(double dx, double dy, double windowHeight) {
  const double radiansPerPixel = std::numbers::pi / std::max(windowHeight, 1.0);
  yaw_ -= dx * radiansPerPixel;
  pitch_ = std::clamp(pitch_ + dy * radiansPerPixel, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(double dx, double dy, double windowHeight) {
  const Vec3d forward = unit(target_ - eye(), {0.0, 0.0, -1.0});
  const Vec3d right = unit(cross(forward, up_), east_);
  const Vec3d screenUp = cross(right, forward);
  // World units per pixel at the target's depth, so the point under the cursor stays there.
  const double halfHeight =
      distance_ * std::tan(0.5 * static_cast<double>(fovY_) * std::numbers::pi / 180.0);
  const double perPixel = 2.0 * halfHeight / std::max(windowHeight, 1.0);
  target_ += (right * -dx + screenUp * dy) * perPixel;
}

void OrbitCamera::zoom(double steps) {
  distance_ = std::clamp(distance_ * std::pow(0.85, steps), 1e-4, 1e7);
}

Camera OrbitCamera::camera(std::uint32_t width, std::uint32_t height) const {
  return Camera::lookAt(Vec3f(eye()), Vec3f(target_), Vec3f(up_), fovY_, width, height, hither_);
}

}  // namespace tg::view_tool
