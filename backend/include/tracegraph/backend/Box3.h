/// @file Box3.h
/// Axis-aligned bounding boxes.
#pragma once

#include <limits>

#include "tracegraph/backend/Vec3.h"

namespace tg {

/// Axis-aligned box; an empty box has lower > upper so that extend() works from it.
template <typename T>
struct Box3 {
  Vec3<T> lower{std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity(),
                std::numeric_limits<T>::infinity()};
  Vec3<T> upper{-std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity(),
                -std::numeric_limits<T>::infinity()};

  constexpr Box3() = default;
  constexpr Box3(const Vec3<T>& lo, const Vec3<T>& hi) : lower(lo), upper(hi) {}

  constexpr bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  constexpr void extend(const Vec3<T>& p) { lower = min(lower, p); upper = max(upper, p); }
  constexpr void extend(const Box3& b) { lower = min(lower, b.lower); upper = max(upper, b.upper); }
  constexpr Vec3<T> extent() const { return upper - lower; }
  constexpr Vec3<T> center() const { return (lower + upper) * T(0.5); }
  /// Surface area (0 for an empty box).
  constexpr T area() const {
    if (empty()) return T(0);
    const Vec3<T> d = extent();
    return T(2) * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  constexpr bool contains(const Vec3<T>& p) const {
    return p.x >= lower.x && p.x <= upper.x && p.y >= lower.y && p.y <= upper.y &&
           p.z >= lower.z && p.z <= upper.z;
  }
  constexpr bool contains(const Box3& b) const { return contains(b.lower) && contains(b.upper); }
  constexpr bool operator==(const Box3& o) const = default;
};

using Box3f = Box3<float>;
using Box3d = Box3<double>;

template <typename T>
constexpr Box3<T> intersection(const Box3<T>& a, const Box3<T>& b) {
  return {max(a.lower, b.lower), min(a.upper, b.upper)};
}

}  // namespace tg
