/// @file KeyInterval.h
/// Locating a fraction among an interpolator's keys.
#pragma once

#include <cstddef>
#include <vector>

namespace tg::nodes {

/// Where a fraction falls among keys: between key `index` and `index + 1` at `weight` in
/// [0, 1] (weight 0 and index == last outside the key range, which clamps as VRML does).
struct KeyInterval {
  /// The key at or before the fraction.
  std::size_t index = 0;
  /// Position between key index and the next, in [0, 1].
  float weight = 0.0f;
};

/// Finds the interval of `fraction` in non-decreasing `keys` (which must not be empty).
KeyInterval findKeyInterval(const std::vector<float>& keys, float fraction);

}  // namespace tg::nodes
