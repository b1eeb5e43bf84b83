/// @file Camera.h
/// Perspective camera.
#pragma once

#include "tracegraph/scenegraph/CameraNode.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Perspective camera placed by the current matrix (VRML Viewpoint, BART "v"). Unrotated it
/// looks along -Z with +Y up. SceneGraph::camera() gives the first camera in world space.
class Camera : public CameraNode {
 public:
  /// A new camera at (0, 0, 10) looking at the origin.
  static ref_ptr<Camera> create() { return ref_ptr<Camera>(new Camera()); }
  std::string_view className() const override { return "Camera"; }
  CameraData cameraData() const override;
  /// Sets position and orientation so that the camera at `from` looks at `at` with `up`
  /// roughly up (BART's from/at/up). Leaves the camera unchanged for degenerate input.
  void lookAt(const Vec3f& from, const Vec3f& at, const Vec3f& up);

  /// Eye position in the node's frame.
  SFVec3f position{*this, "position", ChangeKind::Parameter, Vec3f(0.0f, 0.0f, 10.0f)};
  /// Rotation of the default view (looking along -Z, +Y up).
  SFRotation orientation{*this, "orientation", ChangeKind::Parameter};
  SFFloat fov{*this, "fov", ChangeKind::Parameter, 0.785398f};  ///< vertical, radians
  /// Near distance: primary rays start this far along the view ray.
  SFFloat hither{*this, "hither", ChangeKind::Parameter, 0.01f};
  SFFloat aspect{*this, "aspect", ChangeKind::Parameter, 1.0f};  ///< width / height

 protected:
  Camera() = default;
};

}  // namespace tg::nodes
