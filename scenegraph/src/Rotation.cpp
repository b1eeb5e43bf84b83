#include "tracegraph/scenegraph/Rotation.h"

#include <algorithm>
#include <cmath>

namespace tg {
namespace {

Quaternion normalized(const Quaternion& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (n == 0.0) return {};
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

}  // namespace

Quaternion toQuaternion(const Rotation& r) {
  const Vec3d axis(r.axis);
  const double len = length(axis);
  const double angle = static_cast<double>(r.angle);
  if (len == 0.0 || angle == 0.0) return {};
  const double s = std::sin(0.5 * angle) / len;
  return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}

Rotation toRotation(const Quaternion& in) {
  Quaternion q = normalized(in);
  if (q.w < 0.0) q = {-q.w, -q.x, -q.y, -q.z};
  const double s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  Rotation r;
  if (s < 1e-300) return r;  // identity: keep the default axis
  // atan2 keeps small angles accurate where acos(w) would lose half the digits.
  r.angle = static_cast<float>(2.0 * std::atan2(s, q.w));
  r.axis = Vec3f(Vec3d(q.x / s, q.y / s, q.z / s));
  return r;
}

Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quaternion slerp(const Quaternion& a, const Quaternion& bIn, double t) {
  Quaternion b = bIn;
  double d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  // q and -q are the same rotation; flipping one takes the shorter arc.
  if (d < 0.0) {
    b = {-b.w, -b.x, -b.y, -b.z};
    d = -d;
  }
  double wa = 1.0 - t, wb = t;
  // Nearly parallel: sin(theta) ~ 0 would divide by almost nothing; linear is exact enough.
  if (d < 0.9999) {
    const double theta = std::acos(std::clamp(d, -1.0, 1.0));
    const double s = std::sin(theta);
    wa = std::sin((1.0 - t) * theta) / s;
    wb = std::sin(t * theta) / s;
  }
  return normalized(
      {wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z});
}

Quaternion quaternionFromBasis(const Vec3d& x, const Vec3d& y, const Vec3d& z) {
  // Shepperd's method: divide by the largest of the four candidate terms for accuracy.
  const double m00 = x.x, m01 = y.x, m02 = z.x;
  const double m10 = x.y, m11 = y.y, m12 = z.y;
  const double m20 = x.z, m21 = y.z, m22 = z.z;
  const double trace = m00 + m11 + m22;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(trace + 1.0);
    return {0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  }
  if (m00 > m11 && m00 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
    return {(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  }
  if (m11 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
    return {(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  }
  const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
  return {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
}

Affine3d toMatrix(const Quaternion& in) {
  const Quaternion q = normalized(in);
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  Affine3d m;
  m.m[0][0] = 1.0 - 2.0 * (yy + zz);
  m.m[0][1] = 2.0 * (xy - wz);
  m.m[0][2] = 2.0 * (xz + wy);
  m.m[1][0] = 2.0 * (xy + wz);
  m.m[1][1] = 1.0 - 2.0 * (xx + zz);
  m.m[1][2] = 2.0 * (yz - wx);
  m.m[2][0] = 2.0 * (xz - wy);
  m.m[2][1] = 2.0 * (yz + wx);
  m.m[2][2] = 1.0 - 2.0 * (xx + yy);
  return m;
}

Affine3d rotationMatrix(const Rotation& r) {
  if (r.angle == 0.0f) return Affine3d{};
  return toMatrix(toQuaternion(r));
}

Vec3d rotate(const Quaternion& q, const Vec3d& v) {
  return toMatrix(q).transformVector(v);
}

}  // namespace tg
