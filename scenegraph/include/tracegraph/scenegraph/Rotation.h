/// @file Rotation.h
/// Rotations as VRML writes them (axis + angle in radians) and the double-precision
/// quaternion algebra used to compose and interpolate them.
#pragma once

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Rotation by `angle` radians about `axis` (right-handed), the value type of SFRotation.
/// A zero axis means no rotation.
struct Rotation {
  /// Axis of rotation (need not be unit).
  Vec3f axis{0.0f, 0.0f, 1.0f};
  /// Angle in radians, right-handed about the axis.
  float angle = 0.0f;
  /// Exact equality of axis and angle.
  bool operator==(const Rotation&) const = default;
};

/// Unit quaternion w + xi + yj + zk in double, for composition and slerp.
struct Quaternion {
  ///@{
  /// Real part w and imaginary parts x, y, z.
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  ///@}
};

/// The quaternion of a rotation (identity for a zero axis).
Quaternion toQuaternion(const Rotation& r);
/// Axis-angle form of a unit quaternion, angle in [0, pi].
Rotation toRotation(const Quaternion& q);
/// Hamilton product: applying b first, then a.
Quaternion operator*(const Quaternion& a, const Quaternion& b);
/// Spherical linear interpolation along the shorter arc, t in [0, 1].
Quaternion slerp(const Quaternion& a, const Quaternion& b, double t);
/// The rotation as an affine matrix, composed in double.
Affine3d toMatrix(const Quaternion& q);
/// The rotation as an affine matrix, composed in double.
Affine3d rotationMatrix(const Rotation& r);
/// The quaternion of the rotation whose matrix has the columns x, y, z (an orthonormal,
/// right-handed basis: the images of the unit axes).
Quaternion quaternionFromBasis(const Vec3d& x, const Vec3d& y, const Vec3d& z);
/// Rotates a vector.
Vec3d rotate(const Quaternion& q, const Vec3d& v);

}  // namespace tg
