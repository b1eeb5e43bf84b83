/// @file PositionInterpolator.h
/// Keyframed position (linear) interpolation.
#pragma once

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// VRML PositionInterpolator: maps `set_fraction` through `key`/`keyValue` to `value_changed`,
/// position (linear), e.g. to drive Transform.translation or scale. Fractions outside the keys
/// clamp to the first or last value.
class PositionInterpolator : public Animator {
 public:
  /// A new interpolator without keys.
  static ref_ptr<PositionInterpolator> create() {
    return ref_ptr<PositionInterpolator>(new PositionInterpolator());
  }
  std::string_view className() const override { return "PositionInterpolator"; }
  void evaluate(double time) override;

  /// Input: the fraction to interpolate at (usually from a TimeSensor).
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  /// Input: key fractions, non-decreasing.
  MFFloat key{*this, "key", ChangeKind::Parameter};
  /// Input: one value per key.
  MFVec3f keyValue{*this, "keyValue", ChangeKind::Parameter};
  /// Output.
  SFVec3f value_changed{*this, "value_changed", ChangeKind::Parameter};

 protected:
  PositionInterpolator() = default;
};

}  // namespace tg::nodes
