#include "tracegraph/backend/Affine.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tg {

template <typename T>
Affine3<T> Affine3<T>::rotation(const Vec3<T>& axis, T degrees) {
  return rotationRadians(axis, degrees * std::numbers::pi_v<T> / T(180));
}

template <typename T>
Affine3<T> Affine3<T>::rotationRadians(const Vec3<T>& axis, T radians) {
  const T len = length(axis);
  if (!(len > T(0))) return identity();
  const Vec3<T> a = axis / len;
  const T c = std::cos(radians), s = std::sin(radians), k = T(1) - c;
  Affine3 r;
  r.m[0][0] = c + a.x * a.x * k;
  r.m[0][1] = a.x * a.y * k - a.z * s;
  r.m[0][2] = a.x * a.z * k + a.y * s;
  r.m[1][0] = a.y * a.x * k + a.z * s;
  r.m[1][1] = c + a.y * a.y * k;
  r.m[1][2] = a.y * a.z * k - a.x * s;
  r.m[2][0] = a.z * a.x * k - a.y * s;
  r.m[2][1] = a.z * a.y * k + a.x * s;
  r.m[2][2] = c + a.z * a.z * k;
  return r;
}

template <typename T>
bool Affine3<T>::isFinite() const {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(m[r][c])) return false;
  return true;
}

template <typename T>
bool Affine3<T>::isSingular() const {
  // Work in double whatever T is: the test must not itself underflow for small scales.
  const double det = static_cast<double>(determinant());
  double colProduct = 1.0;
  for (int c = 0; c < 3; ++c) {
    const auto x = static_cast<double>(m[0][c]), y = static_cast<double>(m[1][c]),
               z = static_cast<double>(m[2][c]);
    colProduct *= std::sqrt(x * x + y * y + z * z);
  }
  // Hadamard: |det| <= product of column lengths, with equality for orthogonal columns.
  // A ratio near machine epsilon means the columns are (numerically) linearly dependent.
  return !(colProduct > 0.0) || !(std::abs(det) > 1e-12 * colProduct);
}

template <typename T>
std::optional<Affine3<T>> Affine3<T>::inverse() const {
  if (!isFinite() || isSingular()) return std::nullopt;
  const T det = determinant();
  const T id = T(1) / det;
  Affine3 r;
  r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
  r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
  r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
  r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
  r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
  r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
  r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
  r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
  r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
  const Vec3<T> t{m[0][3], m[1][3], m[2][3]};
  for (int i = 0; i < 3; ++i) r.m[i][3] = -(r.m[i][0] * t.x + r.m[i][1] * t.y + r.m[i][2] * t.z);
  if (!r.isFinite()) return std::nullopt;
  return r;
}

template <typename T>
Box3<T> Affine3<T>::transformBox(const Box3<T>& b) const {
  Box3<T> out;
  if (b.empty()) return out;
  // Per output axis, each term m[r][c] * x takes its smaller value at one end of the box's
  // c-interval and its larger at the other (Arvo 1990, "Transforming axis-aligned bounding
  // boxes"). The terms are added in transformPoint's order, and rounded addition never
  // decreases when an operand grows, so the sums are bit for bit the extreme coordinates of
  // the eight transformed corners, at a third of the work.
  const bool finite = tg::isFinite(b.lower) && tg::isFinite(b.upper);
  for (int r = 0; r < 3; ++r) {
    T lo = T(0), hi = T(0);
    for (int c = 0; c < 3; ++c) {
      T x = m[r][c] * b.lower[c], y = m[r][c] * b.upper[c];
      // A zero entry contributes nothing, even for an infinite box (0 * inf would be NaN). The
      // test stays off the common path: min and max of finite terms need no branch.
      if (!finite && m[r][c] == T(0)) x = y = T(0);
      const T small = std::min(x, y), large = std::max(x, y);
      lo = c == 0 ? small : lo + small;
      hi = c == 0 ? large : hi + large;
    }
    out.lower[r] = lo + m[r][3];
    out.upper[r] = hi + m[r][3];
  }
  return out;
}

template struct Affine3<float>;
template struct Affine3<double>;

}  // namespace tg
