/// @file ScalarInterpolator.h
/// Keyframed scalar (linear) interpolation.
#pragma once

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// VRML ScalarInterpolator: maps `set_fraction` through `key`/`keyValue` to `value_changed`,
/// scalar (linear), e.g. to drive a morph weight or a light intensity. Fractions outside the keys
/// clamp to the first or last value.
class ScalarInterpolator : public Animator {
 public:
  /// A new interpolator without keys.
  static ref_ptr<ScalarInterpolator> create() {
    return ref_ptr<ScalarInterpolator>(new ScalarInterpolator());
  }
  std::string_view className() const override { return "ScalarInterpolator"; }
  void evaluate(double time) override;

  /// Input: the fraction to interpolate at (usually from a TimeSensor).
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  /// Input: key fractions, non-decreasing.
  MFFloat key{*this, "key", ChangeKind::Parameter};
  /// Input: one value per key.
  MFFloat keyValue{*this, "keyValue", ChangeKind::Parameter};
  /// Output.
  SFFloat value_changed{*this, "value_changed", ChangeKind::Parameter};

 protected:
  ScalarInterpolator() = default;
};

}  // namespace tg::nodes
