#include "tracegraph/backend/render/Camera.h"

#include <cmath>
#include <numbers>
#include <string>

#include "../NormalizePair.h"
#include "tracegraph/backend/Error.h"

namespace tg {

Camera::Camera(const CameraParams& params) : params_(params) {
  if (!isFinite(params.eye) || !isFinite(params.viewDirection) || !isFinite(params.up))
    throw Error("Camera: eye, view direction and up must be finite");
  if (!(params.fovYDegrees > 0.0f && params.fovYDegrees < 180.0f))
    throw Error("Camera: vertical field of view " + std::to_string(params.fovYDegrees) +
                " is not in (0, 180) degrees");
  if (!(params.hither >= 0.0f) || !std::isfinite(params.hither))
    throw Error("Camera: hither must be finite and >= 0");
  if (params.width == 0 || params.height == 0) throw Error("Camera: image size is zero");
  const Vec3d view(params.viewDirection);
  const double viewLength = length(view);
  if (!(viewLength > 0.0)) throw Error("Camera: view direction is zero");
  forward_ = view / viewLength;
  const Vec3d side = cross(forward_, Vec3d(params.up));
  const double sideLength = length(side);
  // Relative test: `up` nearly parallel to the view leaves the roll undefined.
  if (!(sideLength > 1e-9 * length(Vec3d(params.up))))
    throw Error("Camera: up vector is zero or parallel to the view direction");
  right_ = side / sideLength;
  upAxis_ = cross(right_, forward_);
  halfHeight_ = std::tan(static_cast<double>(params.fovYDegrees) * std::numbers::pi / 360.0);
  halfWidth_ = halfHeight_ * static_cast<double>(params.width) / static_cast<double>(params.height);
}

Camera Camera::lookAt(const Vec3f& eye, const Vec3f& target, const Vec3f& up, float fovYDegrees,
                      std::uint32_t width, std::uint32_t height, float hither) {
  CameraParams p;
  p.eye = eye;
  p.viewDirection = target - eye;
  p.up = up;
  p.fovYDegrees = fovYDegrees;
  p.width = width;
  p.height = height;
  p.hither = hither;
  return Camera(p);
}

Ray Camera::primaryRay(std::uint32_t x, std::uint32_t y) const {
  return primaryRayAt(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5);
}

Ray Camera::primaryRayAt(double px, double py) const {
  return rayThroughPlane(planeX(px), planeY(py));
}

double Camera::planeX(double px) const {
  // Normalised device coordinates in [-1, 1], scaled to the image plane.
  return (2.0 * px / static_cast<double>(params_.width) - 1.0) * halfWidth_;
}

double Camera::planeY(double py) const {
  // y flips because row 0 is the top row.
  return (1.0 - 2.0 * py / static_cast<double>(params_.height)) * halfHeight_;
}

Ray Camera::rayThroughPlane(double sx, double sy) const {
  const Vec3d d = forward_ + right_ * sx + upAxis_ * sy;
  Ray ray;
  ray.origin = params_.eye;
  ray.direction = Vec3f(d / length(d));
  ray.tnear = params_.hither;
  ray.tfar = kInfinity;
  return ray;
}

void Camera::rayPairThroughPlane(double sx0, double sx1, double sy, Ray* out) const {
#if defined(__SSE2__)
  // rayThroughPlane's operations in its order, lane by lane (no fused multiply-add in this
  // baseline unit; square root, division and the rounding to float are correctly rounded in
  // vectors as in scalars).
  const __m128d sx = _mm_set_pd(sx1, sx0), syv = _mm_set1_pd(sy);
  const auto component = [&](double f, double r, double u) {
    return _mm_add_pd(_mm_add_pd(_mm_set1_pd(f), _mm_mul_pd(_mm_set1_pd(r), sx)),
                      _mm_mul_pd(_mm_set1_pd(u), syv));
  };
  Vec3f directions[2];
  detail::normalizePair(component(forward_.x, right_.x, upAxis_.x),
                        component(forward_.y, right_.y, upAxis_.y),
                        component(forward_.z, right_.z, upAxis_.z), directions);
  for (int k = 0; k < 2; ++k) {
    Ray& ray = out[k];
    ray.origin = params_.eye;
    ray.direction = directions[k];
    ray.tnear = params_.hither;
    ray.tfar = kInfinity;
  }
#else
  out[0] = rayThroughPlane(sx0, sy);
  out[1] = rayThroughPlane(sx1, sy);
#endif
}

}  // namespace tg
