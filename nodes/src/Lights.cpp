// Parameter packing of the three light kinds.
#include "tracegraph/nodes/DirectionalLight.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/SpotLight.h"

namespace tg::nodes {

LightData PointLight::lightData() const {
  LightData d;
  d.kind = LightKind::Point;
  d.on = on.getValue();
  d.color = color.getValue();
  d.intensity = intensity.getValue();
  d.position = location.getValue();
  d.attenuation = attenuation.getValue();
  return d;
}

LightData DirectionalLight::lightData() const {
  LightData d;
  d.kind = LightKind::Directional;
  d.on = on.getValue();
  d.color = color.getValue();
  d.intensity = intensity.getValue();
  d.direction = direction.getValue();
  return d;
}

LightData SpotLight::lightData() const {
  LightData d;
  d.kind = LightKind::Spot;
  d.on = on.getValue();
  d.color = color.getValue();
  d.intensity = intensity.getValue();
  d.position = location.getValue();
  d.direction = direction.getValue();
  d.cutOffAngle = cutOffAngle.getValue();
  d.beamWidth = beamWidth.getValue();
  d.attenuation = attenuation.getValue();
  return d;
}

}  // namespace tg::nodes
