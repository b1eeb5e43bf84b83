/// @file LightNode.h
/// The light role and the light parameters, in the light's frame or in world space.
#pragma once

#include <cstdint>

#include "tracegraph/backend/Vec3.h"
#include "tracegraph/scenegraph/Color.h"
#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Kinds of light.
enum class LightKind : std::uint8_t { Point, Directional, Spot };

/// A light's parameters. LightNode::lightData() gives them in the node's own frame; the
/// SceneGraph maps position and direction through the current matrix to world space.
struct LightData {
  /// Point, directional or spot.
  LightKind kind = LightKind::Point;
  /// False: the light contributes nothing.
  bool on = true;
  /// Linear RGB colour.
  Color color{1.0f, 1.0f, 1.0f};
  /// Scale of the colour.
  float intensity = 1.0f;
  Vec3f position{0.0f, 0.0f, 1.0f};     ///< point and spot lights
  Vec3f direction{0.0f, 0.0f, -1.0f};   ///< directional and spot lights (unit in world space)
  Vec3f attenuation{1.0f, 0.0f, 0.0f};  ///< constant, linear, quadratic (VRML)
  float cutOffAngle = 0.785398f;        ///< spot: no light beyond this angle from the axis, radians
  float beamWidth = 1.570796f;          ///< spot: full light within this angle of the axis (X3D)
};

/// Role of PointLight, DirectionalLight and SpotLight. Lights are global: wherever they sit in
/// the graph they light the whole scene (VRML's global lights), placed by the current matrix.
class LightNode : public Node {
 public:
  /// The parameters in the node's frame.
  virtual LightData lightData() const = 0;
  void accept(NodeVisitor& visitor) override;

 protected:
  LightNode() = default;
};

}  // namespace tg
