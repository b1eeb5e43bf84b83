/// @file CameraNode.h
/// The camera role and the camera parameters.
#pragma once

#include "tracegraph/backend/Vec3.h"
#include "tracegraph/scenegraph/Node.h"
#include "tracegraph/scenegraph/Rotation.h"

namespace tg {

/// A perspective camera. As in VRML, an unrotated camera looks along -Z with +Y up;
/// `orientation` rotates that frame and `position` places it (in the node's frame).
struct CameraData {
  /// Eye position.
  Vec3f position{0.0f, 0.0f, 10.0f};
  /// Rotation of the default view (along -Z, +Y up).
  Rotation orientation;
  float fov = 0.785398f;  ///< full vertical field of view, radians
  float hither = 0.01f;   ///< near distance: primary rays start this far along the view ray
  float aspect = 1.0f;    ///< width / height
};

/// Role of Camera.
class CameraNode : public Node {
 public:
  /// The parameters in the node's frame.
  virtual CameraData cameraData() const = 0;
  void accept(NodeVisitor& visitor) override;

 protected:
  CameraNode() = default;
};

}  // namespace tg
