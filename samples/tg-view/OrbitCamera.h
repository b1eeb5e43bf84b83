// The mouse-driven camera of tg-view: orbits a target point about the scene's up axis.
#pragma once

#include <cstdint>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/backend/render/Camera.h"

namespace tg::view_tool {

/// Orbit, pan and zoom around a target. It starts from whatever camera the scene showed when
/// the user first dragged, so taking over the view never makes it jump.
class OrbitCamera {
 public:
  /// Takes over from `current`: same eye, view direction, up and field of view. The target is
  /// placed on the view ray at the depth of the scene's centre, so orbiting circles the scene.
  void takeOver(const Camera& current, const Box3f& sceneBounds);
  /// True once takeOver() was called.
  bool active() const { return active_; }

  /// Turns the view; dx, dy in window pixels (a full window width is about a half turn).
  void orbit(double dx, double dy, double windowHeight);
  /// Moves eye and target together in the image plane, as if dragging the scene by the cursor.
  void pan(double dx, double dy, double windowHeight);
  /// Moves towards (steps > 0) or away from the target.
  void zoom(double steps);

  /// The camera for a width x height frame.
  Camera camera(std::uint32_t width, std::uint32_t height) const;

 private:
  Vec3d eye() const;

  bool active_ = false;
  Vec3d target_;
  Vec3d up_{0.0, 1.0, 0.0};     ///< orbit axis: the scene camera's up
  Vec3d east_{1.0, 0.0, 0.0};   ///< horizontal reference direction (yaw 0), perpendicular to up
  Vec3d north_{0.0, 0.0, 1.0};  ///< cross(up, east)
  double yaw_ = 0.0, pitch_ = 0.0, distance_ = 1.0;
  float fovY_ = 45.0f, hither_ = 0.0f;
};

}  // namespace tg::view_tool
