// Switch selection (Separator and Group need no code beyond their headers).
#include "tracegraph/nodes/Switch.h"

namespace tg::nodes {

bool Switch::isChildActive(std::size_t index) const {
  const std::int32_t which = whichChild.getValue();
  if (which == kAll) return true;
  return which >= 0 && static_cast<std::size_t>(which) == index;
}

}  // namespace tg::nodes
