/// @file Box3.h
/// Axis-aligned bounding boxes.
#pragma once

#include <limits>

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Axis-aligned box; an empty box has lower > upper so that extend() works from it.
template <typename T>
struct Box3 {
  /// Minimum corner.
  Vec3<T> lower{std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity(),
                std::numeric_limits<T>::infinity()};
  /// Maximum corner.
  Vec3<T> upper{-std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity(),
                -std::numeric_limits<T>::infinity()};

  constexpr Box3() = default;
  /// The box from lo to hi.
  constexpr Box3(const Vec3<T>& lo, const Vec3<T>& hi) : lower(lo), upper(hi) {}

  /// True when lower > upper on some axis (holds no point).
  constexpr bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  /// Grows the box to contain p.
  constexpr void extend(const Vec3<T>& p) { lower = min(lower, p); upper = max(upper, p); }
  /// Grows the box to contain b.
  constexpr void extend(const Box3& b) { lower = min(lower, b.lower); upper = max(upper, b.upper); }
  /// upper - lower.
  constexpr Vec3<T> extent() const { return upper - lower; }
  /// Midpoint of lower and upper.
  constexpr Vec3<T> center() const { return (lower + upper) * T(0.5); }
  /// Surface area (0 for an empty box).
  constexpr T area() const {
    if (empty()) return T(0);
    const Vec3<T> d = extent();
    return T(2) * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  /// True when p lies in the box, faces included.
  constexpr bool contains(const Vec3<T>& p) const {
    return p.x >= lower.x && p.x <= upper.x && p.y >= lower.y && p.y <= upper.y &&
           p.z >= lower.z && p.z <= upper.z;
  }
  /// True when b lies in the box, faces included.
  constexpr bool contains(const Box3& b) const { return contains(b.lower) && contains(b.upper); }
  /// Exact equality of both corners.
  constexpr bool operator==(const Box3& o) const = default;
};

/// Box of floats.
using Box3f = Box3<float>;
/// Box of doubles.
using Box3d = Box3<double>;

template <typename T>
/// The box common to a and b (empty when they do not overlap).
constexpr Box3<T> intersection(const Box3<T>& a, const Box3<T>& b) {
  return {max(a.lower, b.lower), min(a.upper, b.upper)};
}

}  // namespace tg
