/// @file DirectionalLight.h
/// Light with parallel rays from infinitely far away.
#pragma once

#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Directional light shining along `direction` (rotated by the current matrix).
class DirectionalLight : public LightNode {
 public:
  /// A new white light shining along -Z.
  static ref_ptr<DirectionalLight> create() {
    return ref_ptr<DirectionalLight>(new DirectionalLight());
  }
  std::string_view className() const override { return "DirectionalLight"; }
  LightData lightData() const override;

  /// False switches the light off (it stays listed).
  SFBool on{*this, "on", ChangeKind::Parameter, true};
  /// Linear RGB colour (the renderer multiplies it by the intensity).
  SFColor color{*this, "color", ChangeKind::Parameter, Color{1.0f, 1.0f, 1.0f}};
  /// Scale of the colour.
  SFFloat intensity{*this, "intensity", ChangeKind::Parameter, 1.0f};
  /// Direction the light travels, in the node's frame.
  SFVec3f direction{*this, "direction", ChangeKind::Parameter, Vec3f(0.0f, 0.0f, -1.0f)};

 protected:
  DirectionalLight() = default;
};

}  // namespace tg::nodes
