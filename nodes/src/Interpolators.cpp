// The VRML interpolators: key search, then a linear or spherical blend.
#include <algorithm>

#include "tracegraph/nodes/CoordinateInterpolator.h"
#include "tracegraph/nodes/KeyInterval.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/ScalarInterpolator.h"
#include "tracegraph/scenegraph/Rotation.h"

namespace tg::nodes {
namespace {

Vec3f lerp(const Vec3f& a, const Vec3f& b, float w) {
  return a + (b - a) * w;
}

}  // namespace

void PositionInterpolator::evaluate(double) {
  const auto& keys = key.getValues();
  const auto& values = keyValue.getValues();
  const std::size_t n = std::min(keys.size(), values.size());
  if (n == 0) return;
  const std::vector<float> k(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(n));
  const KeyInterval s = findKeyInterval(k, set_fraction.getValue());
  value_changed.setValue(s.weight == 0.0f ? values[s.index]
                                          : lerp(values[s.index], values[s.index + 1], s.weight));
}

void ScalarInterpolator::evaluate(double) {
  const auto& keys = key.getValues();
  const auto& values = keyValue.getValues();
  const std::size_t n = std::min(keys.size(), values.size());
  if (n == 0) return;
  const std::vector<float> k(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(n));
  const KeyInterval s = findKeyInterval(k, set_fraction.getValue());
  value_changed.setValue(s.weight == 0.0f ? values[s.index]
                                          : values[s.index] +
                                                (values[s.index + 1] - values[s.index]) * s.weight);
}

void OrientationInterpolator::evaluate(double) {
  const auto& keys = key.getValues();
  const auto& values = keyValue.getValues();
  const std::size_t n = std::min(keys.size(), values.size());
  if (n == 0) return;
  const std::vector<float> k(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(n));
  const KeyInterval s = findKeyInterval(k, set_fraction.getValue());
  if (s.weight == 0.0f) {
    value_changed.setValue(values[s.index]);
    return;
  }
  const Quaternion q = slerp(toQuaternion(values[s.index]), toQuaternion(values[s.index + 1]),
                             static_cast<double>(s.weight));
  value_changed.setValue(toRotation(q));
}

void CoordinateInterpolator::evaluate(double) {
  const auto& keys = key.getValues();
  const auto& values = keyValue.getValues();
  if (keys.empty() || values.size() < keys.size()) return;
  const std::size_t n = values.size() / keys.size();
  const KeyInterval s = findKeyInterval(keys, set_fraction.getValue());
  const std::size_t a = s.index * n;
  std::vector<Vec3f> out(values.begin() + static_cast<std::ptrdiff_t>(a),
                         values.begin() + static_cast<std::ptrdiff_t>(a + n));
  if (s.weight != 0.0f) {
    const std::size_t b = a + n;
    for (std::size_t i = 0; i < n; ++i) out[i] = lerp(values[a + i], values[b + i], s.weight);
  }
  value_changed.setValues(std::move(out));
}

}  // namespace tg::nodes
