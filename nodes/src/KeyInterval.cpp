#include "tracegraph/nodes/KeyInterval.h"

#include <algorithm>

namespace tg::nodes {

KeyInterval findKeyInterval(const std::vector<float>& keys, float fraction) {
  const std::size_t last = keys.size() - 1;
  if (keys.size() < 2 || !(fraction > keys.front())) return {0, 0.0f};
  if (fraction >= keys.back()) return {last, 0.0f};
  // First key strictly greater than the fraction; the interval starts one before it.
  const auto it = std::upper_bound(keys.begin(), keys.end(), fraction);
  const std::size_t i = static_cast<std::size_t>(it - keys.begin()) - 1;
  const float span = keys[i + 1] - keys[i];
  const float w = span > 0.0f ? (fraction - keys[i]) / span : 0.0f;
  return {i, std::clamp(w, 0.0f, 1.0f)};
}

}  // namespace tg::nodes
