/// @file KochanekBartels.h
/// Keyframe interpolation of the BART animated file format (AFF): Kochanek–Bartels splines for
/// positions and scales, quaternion Kochanek–Bartels tangents with squad for rotations, and
/// step-wise visibility. The rules (segment search, holding the second and the second-to-last
/// key, the 1e-3 cut-offs, the sign fix done segment by segment) follow section 3 of
/// docs/aff-format.md so that animations match the benchmark's reference frames.
#pragma once

#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Quaternion w + xi + yj + zk in double precision. Rotation keys are unit quaternions; the
/// logarithm of one is a pure quaternion, returned here as its vector part.
struct Quatd {
  ///@{
  /// Real part w and imaginary parts x, y, z.
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  ///@}

  /// Rotation by `radians` (right-handed) about `axis`. The axis is normalised first because
  /// 28 robots tracks have axes of length 1.077 or 0.971; a zero axis gives the identity.
  static Quatd fromAxisAngle(const Vec3d& axis, double radians);

  /// The vector part (x, y, z).
  constexpr Vec3d vec() const { return {x, y, z}; }
  /// The conjugate w - xi - yj - zk (the inverse of a unit quaternion).
  constexpr Quatd conjugate() const { return {w, -x, -y, -z}; }
  /// The negation, which represents the same rotation.
  constexpr Quatd operator-() const { return {-w, -x, -y, -z}; }
  /// Hamilton product.
  constexpr Quatd operator*(const Quatd& b) const {
    return {w * b.w - x * b.x - y * b.y - z * b.z, w * b.x + x * b.w + y * b.z - z * b.y,
            w * b.y - x * b.z + y * b.w + z * b.x, w * b.z + x * b.y - y * b.x + z * b.w};
  }
  /// Four-dimensional dot product.
  constexpr double dot(const Quatd& b) const { return w * b.w + x * b.x + y * b.y + z * b.z; }

  /// The rotation matrix, built through axis and angle as the reference does: angle =
  /// 2·acos(w) with w clamped to [-1, 1], axis = normalised vector part (identity when the
  /// vector part vanishes). This also tolerates quaternions that drifted off unit length.
  Affine3d toMatrix() const;
};

/// Logarithm of a unit quaternion cos φ + n sin φ, returned as the vector φ·n. When sin φ is
/// below 1e-3 the vector part is returned unchanged (sin φ ≈ φ there), as in the reference.
Vec3d quatLog(const Quatd& q);
/// Exponential of the pure quaternion v: cos|v| + (v/|v|) sin|v|; for |v| < 1e-3 it returns
/// cos|v| + v, the same cut-off as quatLog.
Quatd quatExp(const Vec3d& v);
/// Spherical interpolation from `a` (u = 0) to `b` (u = 1) along the arc between them as
/// given: it never negates `b` to take the shorter way (squad relies on this). When the sine
/// of the angle between the inputs is below 1e-3 it returns `a`.
Quatd slerpNoFlip(const Quatd& a, const Quatd& b, double u);
/// Right-handed rotation by `radians` about `axis` (normalised here; zero axis → identity),
/// computed in double without a detour through degrees.
Affine3d rotationMatrix(const Vec3d& axis, double radians);

/// Tension, continuity and bias of one key; all zero gives a Catmull–Rom-like spline.
struct KbParams {
  double tension = 0.0;     ///< T: 1 flattens the tangent, -1 doubles it
  double continuity = 0.0;  ///< C: non-zero makes incoming and outgoing tangents differ (a kink)
  double bias = 0.0;        ///< B: weights the previous (B > 0) or next (B < 0) chord
};

/// Kochanek–Bartels spline through three-component keys (AFF `transl` and `scale` channels;
/// each component is interpolated the same way).
///
/// With keys K0…K(n-1) (n ≥ 4), segment s = 1…n-3 runs from Ks to Ks+1; K0 and K(n-1) only shape
/// tangents. Times t ≤ t1 give P1 and t ≥ t(n-2) give P(n-2) (held, never extrapolated);
/// otherwise the first segment (in key order, not time order) whose end time is greater than t
/// is used. Keys are kept in file order: robots' `gun_rot1` concatenates two lists and the
/// reference search lets the second govern only after the first ends.
class KbVectorSpline {
 public:
  /// One key: time, value and tension/continuity/bias.
  struct Key {
    double time = 0.0;  ///< seconds, global animation time
    Vec3d value;        ///< position or scale factors
    KbParams tcb;       ///< shape parameters
  };

  /// Takes the keys in file order. Throws tg::Error when fewer than 4 keys are given or a key
  /// holds a non-finite number.
  explicit KbVectorSpline(std::vector<Key> keys);

  /// Value at time t (see the class comment for the segment rules). NaN gives P1.
  Vec3d evaluate(double t) const;
  /// The keys in file order.
  const std::vector<Key>& keys() const { return keys_; }

 private:
  std::vector<Key> keys_;
};

/// Quaternion Kochanek–Bartels spline with squad interpolation (AFF `rot` channel).
///
/// Keys are axis/angle pairs turned into unit quaternions. Segments are prepared in increasing
/// order; for each, the end key is negated when its dot product with the start key is
/// negative, and the negation persists for later segments. Tangents of a segment are built
/// from the keys' state at that moment, so the key after the segment end is still unflipped
/// (only the robots camera has such opposite pairs). Holding and segment search are as for
/// KbVectorSpline. Whole turns between neighbouring keys are lost (0° and 360° are the same
/// key), exactly as in the reference.
class KbRotationSpline {
 public:
  /// One key: time, rotation axis (any non-zero length), angle in degrees, shape parameters.
  struct Key {
    double time = 0.0;     ///< seconds, global animation time
    Vec3d axis{0, 1, 0};   ///< rotation axis, normalised when converted
    double degrees = 0.0;  ///< right-handed angle about the axis
    KbParams tcb;          ///< shape parameters
  };

  /// Takes the keys in file order and precomputes the squad control points of every segment.
  /// Throws tg::Error when fewer than 4 keys are given or a key holds a non-finite number.
  explicit KbRotationSpline(std::vector<Key> keys);

  /// Unit quaternion at time t (sign as produced by the segment's squad; the sign carries no
  /// meaning). NaN gives the quaternion of key 1.
  Quatd evaluate(double t) const;
  /// Rotation matrix at time t, via Quatd::toMatrix.
  Affine3d matrix(double t) const { return evaluate(t).toMatrix(); }
  /// The keys in file order.
  const std::vector<Key>& keys() const { return keys_; }
  /// The key quaternions after the segment-by-segment sign fix (one per key).
  const std::vector<Quatd>& quaternions() const { return q_; }

 private:
  std::vector<Key> keys_;
  std::vector<Quatd> q_;      ///< sign-fixed key quaternions
  std::vector<Quatd> inner_;  ///< per key i of segment s = i: squad control point A (index 2i)
                              ///< and B (index 2i+1); entries of unused keys stay identity
};

/// One key of a visibility channel.
struct VisibilityKey {
  double time = 0.0;    ///< seconds
  bool visible = true;  ///< flag applying from `time` on
};

/// Visibility at time t: visible before the first key; afterwards the flag of the last key (in
/// file order) whose time is ≤ t. An empty channel is always visible.
bool evaluateVisibility(const std::vector<VisibilityKey>& keys, double t);

}  // namespace tg
