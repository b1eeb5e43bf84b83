/// @file Transform.h
/// Transform node with VRML's decomposed fields.
#pragma once

#include "tracegraph/scenegraph/SField.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg::nodes {

/// Multiplies the current matrix by T * C * R * SR * S * -SR * -C (VRML's order: translation,
/// center, rotation, scaleOrientation, scale), composed in double. Like Inventor's
/// SoTransform it applies to the nodes that follow it inside the enclosing Separator.
class Transform : public TransformNode {
 public:
  /// A new identity transform.
  static ref_ptr<Transform> create() { return ref_ptr<Transform>(new Transform()); }
  std::string_view className() const override { return "Transform"; }
  Affine3d localMatrix() const override;

  /// T: translation.
  SFVec3f translation{*this, "translation", ChangeKind::Transform};
  /// R: rotation about the center.
  SFRotation rotation{*this, "rotation", ChangeKind::Transform};
  /// S: scale along the scale orientation axes.
  SFVec3f scale{*this, "scale", ChangeKind::Transform, Vec3f(1.0f, 1.0f, 1.0f)};
  /// SR: orientation of the scale axes.
  SFRotation scaleOrientation{*this, "scaleOrientation", ChangeKind::Transform};
  /// C: pivot of rotation and scale.
  SFVec3f center{*this, "center", ChangeKind::Transform};

 protected:
  Transform() = default;
};

}  // namespace tg::nodes
