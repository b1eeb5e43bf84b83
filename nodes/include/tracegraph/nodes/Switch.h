/// @file Switch.h
/// Group that traverses one of its children, none or all.
#pragma once

#include <cstdint>

#include "tracegraph/scenegraph/Group.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Group whose `whichChild` selects the child traversed (Inventor SoSwitch, VRML Switch).
/// Like Group it does not isolate state.
class Switch : public Group {
 public:
  /// whichChild value: traverse no child (the default).
  static constexpr std::int32_t kNone = -1;
  /// whichChild value: traverse every child.
  static constexpr std::int32_t kAll = -3;

  /// A new switch with no child selected.
  static ref_ptr<Switch> create() { return ref_ptr<Switch>(new Switch()); }
  std::string_view className() const override { return "Switch"; }
  bool isChildActive(std::size_t index) const override;

  /// Index of the traversed child, kNone or kAll; out-of-range indices select nothing.
  SFInt32 whichChild{*this, "whichChild", ChangeKind::Visibility, kNone};

 protected:
  Switch() = default;
};

}  // namespace tg::nodes
