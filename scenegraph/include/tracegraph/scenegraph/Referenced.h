/// @file Referenced.h
/// Intrusive reference counting shared by nodes and animators.
#pragma once

#include <atomic>

namespace tg {

/// Base of every reference-counted scene-graph object; deleted when its last ref_ptr goes.
///
/// The count lives in the object (as in Open Inventor and VulkanSceneGraph), so a raw pointer
/// handed around the graph can always be turned back into an owning ref_ptr. The count is
/// atomic because renderer threads may hold references while the application thread edits.
class Referenced {
 public:
  Referenced(const Referenced&) = delete;
  Referenced& operator=(const Referenced&) = delete;

  /// Adds one owner.
  void ref() const noexcept { count_.fetch_add(1, std::memory_order_relaxed); }
  /// Drops one owner; deletes the object when it was the last.
  void unref() const noexcept {
    if (count_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }
  /// Current number of owners (for tests and diagnostics).
  int referenceCount() const noexcept { return count_.load(std::memory_order_relaxed); }

 protected:
  Referenced() = default;
  /// Protected so that objects can only be deleted through unref(), never on the stack.
  virtual ~Referenced() = default;

 private:
  mutable std::atomic<int> count_{0};
};

}  // namespace tg
