/// @file Affine.h
/// Affine transforms as 3x4 matrices. Matrices are composed and inverted in double and stored
/// in float for traversal (architecture: "matrices are composed in double and stored in float").
#pragma once

#include <optional>

#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Affine transform p' = L p + t stored row-major as 3 rows of (L | t), acting on column vectors.
template <typename T>
struct Affine3 {
  /// Rows of (L | t); the identity by default.
  T m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  constexpr Affine3() = default;
  /// Conversion between precisions (double -> float rounds each entry once).
  template <typename U>
  constexpr explicit Affine3(const Affine3<U>& o) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m[r][c] = static_cast<T>(o.m[r][c]);
  }

  /// The identity transform.
  static constexpr Affine3 identity() { return Affine3{}; }
  /// Translation by t.
  static constexpr Affine3 translation(const Vec3<T>& t) {
    Affine3 a;
    a.m[0][3] = t.x;
    a.m[1][3] = t.y;
    a.m[2][3] = t.z;
    return a;
  }
  /// Scaling by s along the axes.
  static constexpr Affine3 scaling(const Vec3<T>& s) {
    Affine3 a;
    a.m[0][0] = s.x;
    a.m[1][1] = s.y;
    a.m[2][2] = s.z;
    return a;
  }
  /// Right-handed rotation by `degrees` about `axis` (normalised here; a zero axis gives identity).
  static Affine3 rotation(const Vec3<T>& axis, T degrees);
  /// Right-handed rotation by `radians` about `axis` (normalised here; a zero axis gives
  /// identity); rotation(axis, d) is rotationRadians(axis, d * pi / 180).
  static Affine3 rotationRadians(const Vec3<T>& axis, T radians);
  /// Builds from a row-major 3x4 array.
  static constexpr Affine3 fromRows(const T (&rows)[12]) {
    Affine3 a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) a.m[r][c] = rows[r * 4 + c];
    return a;
  }

  /// L p + t: maps a point.
  constexpr Vec3<T> transformPoint(const Vec3<T>& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  /// L v: maps a direction (no translation).
  constexpr Vec3<T> transformVector(const Vec3<T>& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  /// Applies the transpose of the linear part. Called on the *inverse* matrix it maps
  /// object-space normals to world space (the inverse transpose), which keeps normals
  /// perpendicular to surfaces under non-uniform and mirroring transforms.
  constexpr Vec3<T> transformTransposed(const Vec3<T>& n) const {
    return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
            m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
            m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
  }

  /// Composition: applies b first, then this transform.
  constexpr Affine3 operator*(const Affine3& b) const {
    Affine3 r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) {
        T s = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j];
        if (j == 3) s += m[i][3];
        r.m[i][j] = s;
      }
    }
    return r;
  }

  /// Determinant of the linear part L.
  constexpr T determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }

  /// True when every entry is finite.
  bool isFinite() const;
  /// True when the linear part is numerically singular: its determinant is zero or tiny
  /// relative to the product of its column lengths (a scale of 1e-6 on one axis is *not*
  /// singular by this measure; a zero scale or a rank-deficient matrix is).
  bool isSingular() const;
  /// Inverse, or nothing when the matrix is singular or not finite.
  std::optional<Affine3> inverse() const;
  /// Bounds of a transformed box: the box of its 8 transformed corners, bit for bit as
  /// transformPoint rounds them, computed per matrix term (Arvo) at a third of the cost. An
  /// empty box gives an empty box; a zero matrix entry ignores the box's extent on that axis,
  /// so infinite boxes map without NaN unless infinities of both signs meet in one sum.
  Box3<T> transformBox(const Box3<T>& b) const;

  /// Exact equality of every entry.
  constexpr bool operator==(const Affine3& o) const {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        if (m[r][c] != o.m[r][c]) return false;
    return true;
  }
};

/// Float matrices, as stored for traversal.
using Affine3f = Affine3<float>;
/// Double matrices, as composed and inverted.
using Affine3d = Affine3<double>;

extern template struct Affine3<float>;
extern template struct Affine3<double>;

}  // namespace tg
