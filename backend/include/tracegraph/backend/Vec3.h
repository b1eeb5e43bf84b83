/// @file Vec3.h
/// Three-component vectors in float (geometry, rays) and double (references, matrix algebra).
#pragma once

#include <cmath>
#include <cstddef>

namespace tg {

/// A three-component vector; `T` is float for geometry and rays, double for references.
template <typename T>
struct Vec3 {
  ///@{
  /// The components.
  T x{}, y{}, z{};
  ///@}

  constexpr Vec3() = default;
  /// The vector (x, y, z).
  constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  /// Explicit conversion between precisions (float -> double is exact).
  template <typename U>
  constexpr explicit Vec3(const Vec3<U>& o)
      : x(static_cast<T>(o.x)), y(static_cast<T>(o.y)), z(static_cast<T>(o.z)) {}

  /// Component i (0: x, 1: y, 2: z).
  constexpr T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }
  /// Component i (0: x, 1: y, 2: z), read-only.
  constexpr const T& operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }

  /// Component-wise sum.
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  /// Component-wise difference.
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  /// Component-wise product.
  constexpr Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
  /// Scaled by s.
  constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
  /// Divided by s.
  constexpr Vec3 operator/(T s) const { return {x / s, y / s, z / s}; }
  /// Negated.
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  /// Adds o component-wise.
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  /// Subtracts o component-wise.
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  /// Scales by s.
  constexpr Vec3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
  /// Exact equality of every component.
  constexpr bool operator==(const Vec3& o) const = default;
};

/// Vector of floats: geometry and rays.
using Vec3f = Vec3<float>;
/// Vector of doubles: references and matrix algebra.
using Vec3d = Vec3<double>;

template <typename T>
/// v scaled by s.
constexpr Vec3<T> operator*(T s, const Vec3<T>& v) { return v * s; }
template <typename T>
/// Dot product.
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T>
/// Cross product (right-handed).
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
/// Euclidean length.
inline T length(const Vec3<T>& v) { return std::sqrt(dot(v, v)); }
template <typename T>
/// v divided by its length (not finite for a zero vector).
inline Vec3<T> normalize(const Vec3<T>& v) { return v / length(v); }
template <typename T>
/// Component-wise minimum.
constexpr Vec3<T> min(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <typename T>
/// Component-wise maximum.
constexpr Vec3<T> max(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <typename T>
/// Component-wise absolute value.
inline Vec3<T> abs(const Vec3<T>& v) { return {std::abs(v.x), std::abs(v.y), std::abs(v.z)}; }
template <typename T>
/// The largest component.
constexpr T maxComponent(const Vec3<T>& v) { return v.x > v.y ? (v.x > v.z ? v.x : v.z) : (v.y > v.z ? v.y : v.z); }
/// Index (0, 1, 2) of the largest component.
template <typename T>
constexpr int maxDimension(const Vec3<T>& v) { return v.x >= v.y ? (v.x >= v.z ? 0 : 2) : (v.y >= v.z ? 1 : 2); }
/// True when every component is finite (no NaN, no infinity).
template <typename T>
inline bool isFinite(const Vec3<T>& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace tg
