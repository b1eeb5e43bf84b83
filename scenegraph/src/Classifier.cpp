#include "Classifier.h"

#include <algorithm>

namespace tg::sync {

bool Classifier::driven(const Node& node) {
  return node.isDriven(ChangeKind::Transform | ChangeKind::Points | ChangeKind::Topology);
}

std::uint64_t Classifier::threshold(const State& s) const {
  const std::uint32_t doublings = std::min(s.demotions, options_.maxRestDoublings);
  return std::max<std::uint64_t>(1, std::uint64_t(options_.restFrames) << doublings);
}

std::uint64_t Classifier::restThreshold(const Node& node) const {
  auto it = states_.find(&node);
  return it == states_.end() ? threshold(State{}) : threshold(it->second);
}

bool Classifier::isDynamic(const Node& node) const {
  if (driven(node)) return true;
  auto it = states_.find(&node);
  return it != states_.end() && it->second.moving;
}

bool Classifier::noteChange(Node& node, std::uint64_t frame) {
  const bool wasDynamic = isDynamic(node);
  State& s = states_[&node];
  if (!s.node) s.node = ref_ptr<Node>(&node);
  s.moving = true;
  s.lastChange = frame;
  if (!s.scheduled) {
    queue_.push({frame + threshold(s), &node});
    s.scheduled = true;
  }
  return !wasDynamic;
}

std::vector<ref_ptr<Node>> Classifier::takeDemotions(std::uint64_t frame) {
  std::vector<ref_ptr<Node>> out;
  while (!queue_.empty() && queue_.top().first <= frame) {
    const Node* n = queue_.top().second;
    queue_.pop();
    auto it = states_.find(n);
    if (it == states_.end()) continue;  // forgotten
    State& s = it->second;
    s.scheduled = false;
    if (!s.moving) continue;
    const std::uint64_t due = s.lastChange + threshold(s);
    if (due > frame) {
      queue_.push({due, n});  // it moved again meanwhile: look again when that rest ends
      s.scheduled = true;
      continue;
    }
    s.moving = false;
    // A driven node stays dynamic through its connection; it has not changed class.
    if (driven(*s.node)) continue;
    ++s.demotions;
    out.push_back(s.node);
  }
  return out;
}

void Classifier::forget(const Node* node) {
  states_.erase(node);
}

}  // namespace tg::sync
