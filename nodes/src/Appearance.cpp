// Material and camera parameter packing.
#include <cmath>

#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/Material.h"

namespace tg::nodes {

MaterialData Material::materialData() const {
  MaterialData d;
  d.ambient = ambientColor.getValue();
  d.diffuse = diffuseColor.getValue();
  d.specular = specularColor.getValue();
  d.emissive = emissiveColor.getValue();
  d.shininess = shininess.getValue();
  d.transmittance = transmittance.getValue();
  d.ior = ior.getValue();
  return d;
}

CameraData Camera::cameraData() const {
  CameraData d;
  d.position = position.getValue();
  d.orientation = orientation.getValue();
  d.fov = fov.getValue();
  d.hither = hither.getValue();
  d.aspect = aspect.getValue();
  return d;
}

void Camera::lookAt(const Vec3f& from, const Vec3f& at, const Vec3f& up) {
  const Vec3d f(from), a(at), u(up);
  Vec3d back = f - a;  // the camera's +Z points away from what it looks at
  if (length(back) == 0.0 || !isFinite(back)) return;
  back = normalize(back);
  Vec3d right = cross(u, back);
  if (length(right) == 0.0) return;
  right = normalize(right);
  // The rotation whose matrix has the columns right, up and back.
  position.setValue(from);
  orientation.setValue(toRotation(quaternionFromBasis(right, cross(back, right), back)));
}

}  // namespace tg::nodes
