/// @file OrientationInterpolator.h
/// Keyframed orientation (spherical linear interpolation.
#pragma once

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// VRML OrientationInterpolator: maps `set_fraction` through `key`/`keyValue` to `value_changed`,
/// orientation (spherical linear, shorter arc), e.g. to drive Transform.rotation. Fractions outside
/// the keys clamp to the first or last value.
class OrientationInterpolator : public Animator {
 public:
  /// A new interpolator without keys.
  static ref_ptr<OrientationInterpolator> create() {
    return ref_ptr<OrientationInterpolator>(new OrientationInterpolator());
  }
  std::string_view className() const override { return "OrientationInterpolator"; }
  void evaluate(double time) override;

  /// Input: the fraction to interpolate at (usually from a TimeSensor).
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  /// Input: key fractions, non-decreasing.
  MFFloat key{*this, "key", ChangeKind::Parameter};
  /// Input: one value per key.
  MFRotation keyValue{*this, "keyValue", ChangeKind::Parameter};
  /// Output.
  SFRotation value_changed{*this, "value_changed", ChangeKind::Parameter};

 protected:
  OrientationInterpolator() = default;
};

}  // namespace tg::nodes
