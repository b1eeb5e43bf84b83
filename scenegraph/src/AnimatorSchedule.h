/// @file AnimatorSchedule.h
/// Which animators feed the graph and in which order to evaluate them (internal).
#pragma once

#include <cstdint>
#include <vector>

#include "tracegraph/scenegraph/Animator.h"

namespace tg::sync {

/// The animators upstream of a set of seed nodes, in dependency order (an animator after
/// every animator it reads from, through connected fields or dependencies()).
class AnimatorSchedule {
 public:
  /// Recomputes the order from the nodes with connected fields (and explicit animators).
  void rebuild(const std::vector<const Node*>& seeds);
  /// Evaluates every animator at `time`, copying outputs to connected fields as it goes.
  void evaluate(double time) const;
  /// The animators in evaluation order.
  const std::vector<ref_ptr<Animator>>& order() const { return order_; }

 private:
  std::vector<ref_ptr<Animator>> order_;
};

}  // namespace tg::sync
