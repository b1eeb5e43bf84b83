/// @file Camera.h
/// The pinhole camera that generates primary rays.
#pragma once

#include <cmath>
#include <cstdint>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// What defines a pinhole camera (the fields of NFF/BART `v` blocks and X3D Viewpoints).
struct CameraParams {
  Vec3f eye{0.0f, 0.0f, 0.0f};             ///< centre of projection
  Vec3f viewDirection{0.0f, 0.0f, -1.0f};  ///< need not be unit; must not be parallel to `up`
  Vec3f up{0.0f, 1.0f, 0.0f};              ///< need not be unit or perpendicular to the view
  float fovYDegrees = 45.0f;               ///< full vertical field of view, in (0, 180)
  float hither = 0.0f;         ///< tnear of primary rays (distance along the unit direction)
  std::uint32_t width = 640;   ///< image width in pixels
  std::uint32_t height = 480;  ///< image height in pixels
};

/// A pinhole camera: pixel (x, y) is sampled at its centre (x + 0.5, y + 0.5); row 0 is the top
/// row of the image and column 0 the left column.
class Camera {
 public:
  /// Validates `params` (finite vectors, non-zero view, up not parallel to the view, field of
  /// view in (0, 180) degrees, hither >= 0, non-zero size) and throws tg::Error otherwise.
  explicit Camera(const CameraParams& params);

  /// Camera at `eye` looking at `target`.
  static Camera lookAt(const Vec3f& eye, const Vec3f& target, const Vec3f& up, float fovYDegrees,
                       std::uint32_t width, std::uint32_t height, float hither = 0.0f);

  /// The primary ray through the centre of pixel (x, y): origin at the eye, unit direction,
  /// tnear = hither, tfar = infinity. x and y may lie outside the image (no clamping).
  Ray primaryRay(std::uint32_t x, std::uint32_t y) const;
  /// Primary ray through the image-plane position (px, py) in pixel units (pixel centres are at
  /// half-integers); primaryRay(x, y) is primaryRayAt(x + 0.5, y + 0.5).
  Ray primaryRayAt(double px, double py) const;
  /// The image-plane coordinate (at distance 1, along the right axis) of pixel position px.
  /// It depends on px alone, so that a block of pixels computes it once per column:
  /// primaryRayAt(px, py) is rayThroughPlane(planeX(px), planeY(py)), bit for bit.
  double planeX(double px) const;
  /// The image-plane coordinate (at distance 1, along the up axis) of pixel position py.
  double planeY(double py) const;
  /// The primary ray through the image-plane point (sx, sy) as planeX and planeY give them.
  Ray rayThroughPlane(double sx, double sy) const;
  /// rayThroughPlane(sx0, sy) into out[0] and rayThroughPlane(sx1, sy) into out[1], bit for
  /// bit, with the two rays' double arithmetic in shared instructions where SSE2 is available
  /// (two square roots and six divisions per pair would otherwise run one by one).
  void rayPairThroughPlane(double sx0, double sx1, double sy, Ray* out) const;

  /// The angle a pixel spans at the image centre, in radians: the spread of a ray cone
  /// through one pixel (Akenine-Moeller et al., "Texture Level of Detail Strategies for
  /// Real-Time Ray Tracing", Ray Tracing Gems, 2019), which sizes texture footprints.
  float pixelSpreadAngle() const {
    return static_cast<float>(std::atan(2.0 * halfHeight_ / static_cast<double>(params_.height)));
  }
  /// The parameters the camera was made from.
  const CameraParams& params() const { return params_; }
  /// Image width in pixels.
  std::uint32_t width() const { return params_.width; }
  /// Image height in pixels.
  std::uint32_t height() const { return params_.height; }

 private:
  CameraParams params_;
  // Orthonormal basis and image-plane scales kept in double: the per-pixel direction is formed
  // and normalised in double and rounded to float once, so its length is 1 within an ulp even
  // for narrow fields of view and large images.
  Vec3d forward_, right_, upAxis_;
  double halfHeight_ = 1.0;  ///< tan(fovY / 2): image-plane half height at distance 1
  double halfWidth_ = 1.0;   ///< halfHeight * width / height (square pixels)
};

}  // namespace tg
