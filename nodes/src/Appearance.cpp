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
  const Vec3d trueUp = cross(back, right);
  // Quaternion of the rotation matrix with columns right, trueUp, back (Shepperd's method).
  const double m00 = right.x, m01 = trueUp.x, m02 = back.x;
  const double m10 = right.y, m11 = trueUp.y, m12 = back.y;
  const double m20 = right.z, m21 = trueUp.z, m22 = back.z;
  Quaternion q;
  const double trace = m00 + m11 + m22;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(trace + 1.0);
    q = {0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  } else if (m00 > m11 && m00 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
    q = {(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  } else if (m11 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
    q = {(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
    q = {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
  }
  position.setValue(from);
  orientation.setValue(toRotation(q));
}

}  // namespace tg::nodes
