#include "tracegraph/nodes/Transform.h"

#include "tracegraph/scenegraph/Rotation.h"

namespace tg::nodes {

Affine3d Transform::localMatrix() const {
  const Vec3d t(translation.getValue());
  const Vec3d c(center.getValue());
  const Rotation& so = scaleOrientation.getValue();
  Affine3d m = Affine3d::translation(t + c) * rotationMatrix(rotation.getValue());
  // The scale-orientation sandwich SR * S * -SR is skipped when SR is the identity, which is
  // also what makes the common case exact (no rotation round trip through sin/cos).
  if (so.angle != 0.0f) {
    const Rotation inverse{so.axis, -so.angle};
    m = m * rotationMatrix(so) * Affine3d::scaling(Vec3d(scale.getValue())) *
        rotationMatrix(inverse);
  } else {
    m = m * Affine3d::scaling(Vec3d(scale.getValue()));
  }
  if (!(c == Vec3d{})) m = m * Affine3d::translation(-c);
  return m;
}

}  // namespace tg::nodes
