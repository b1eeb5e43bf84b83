/// @file SpotLight.h
/// Point light restricted to a cone.
#pragma once

#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Spot light at `location` shining along `direction` (X3D SpotLight): full light within
/// `beamWidth` of the axis, falling off to none at `cutOffAngle` (radians).
class SpotLight : public LightNode {
 public:
  /// A new white spot light at (0, 0, 1) shining along -Z.
  static ref_ptr<SpotLight> create() { return ref_ptr<SpotLight>(new SpotLight()); }
  std::string_view className() const override { return "SpotLight"; }
  LightData lightData() const override;

  /// False switches the light off (it stays listed).
  SFBool on{*this, "on", ChangeKind::Parameter, true};
  /// Linear RGB colour (the renderer multiplies it by the intensity).
  SFColor color{*this, "color", ChangeKind::Parameter, Color{1.0f, 1.0f, 1.0f}};
  /// Scale of the colour.
  SFFloat intensity{*this, "intensity", ChangeKind::Parameter, 1.0f};
  /// Position in the node's frame.
  SFVec3f location{*this, "location", ChangeKind::Parameter, Vec3f(0.0f, 0.0f, 1.0f)};
  /// Direction the light travels, in the node's frame.
  SFVec3f direction{*this, "direction", ChangeKind::Parameter, Vec3f(0.0f, 0.0f, -1.0f)};
  /// No light beyond this angle from the axis, radians.
  SFFloat cutOffAngle{*this, "cutOffAngle", ChangeKind::Parameter, 0.785398f};
  /// Full light within this angle from the axis, radians.
  SFFloat beamWidth{*this, "beamWidth", ChangeKind::Parameter, 1.570796f};
  /// Constant, linear and quadratic attenuation factors.
  SFVec3f attenuation{*this, "attenuation", ChangeKind::Parameter, Vec3f(1.0f, 0.0f, 0.0f)};

 protected:
  SpotLight() = default;
};

}  // namespace tg::nodes
