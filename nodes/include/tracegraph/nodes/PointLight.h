/// @file PointLight.h
/// Light radiating from a point in all directions.
#pragma once

#include "tracegraph/scenegraph/LightNode.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Point light at `location` (placed by the current matrix), VRML attenuation.
class PointLight : public LightNode {
 public:
  /// A new white point light at (0, 0, 1).
  static ref_ptr<PointLight> create() { return ref_ptr<PointLight>(new PointLight()); }
  std::string_view className() const override { return "PointLight"; }
  LightData lightData() const override;

  /// False switches the light off (it stays listed).
  SFBool on{*this, "on", ChangeKind::Parameter, true};
  /// Linear RGB colour (the renderer multiplies it by the intensity).
  SFColor color{*this, "color", ChangeKind::Parameter, Color{1.0f, 1.0f, 1.0f}};
  /// Scale of the colour.
  SFFloat intensity{*this, "intensity", ChangeKind::Parameter, 1.0f};
  /// Position in the node's frame.
  SFVec3f location{*this, "location", ChangeKind::Parameter, Vec3f(0.0f, 0.0f, 1.0f)};
  /// Constant, linear and quadratic attenuation factors.
  SFVec3f attenuation{*this, "attenuation", ChangeKind::Parameter, Vec3f(1.0f, 0.0f, 0.0f)};

 protected:
  PointLight() = default;
};

}  // namespace tg::nodes
