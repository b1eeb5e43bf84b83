/// @file CoordinateInterpolator.h
/// Keyframed interpolation of whole point lists.
#pragma once

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/MField.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// VRML CoordinateInterpolator: `keyValue` holds key.size() lists of n points one after the
/// other; `value_changed` is the linear blend of the two lists around `set_fraction`. Connect
/// a Mesh's points from it to make the mesh deform.
class CoordinateInterpolator : public Animator {
 public:
  /// A new interpolator without keys.
  static ref_ptr<CoordinateInterpolator> create() {
    return ref_ptr<CoordinateInterpolator>(new CoordinateInterpolator());
  }
  std::string_view className() const override { return "CoordinateInterpolator"; }
  void evaluate(double time) override;

  /// Input: the fraction to interpolate at (usually from a TimeSensor).
  SFFloat set_fraction{*this, "set_fraction", ChangeKind::Parameter, 0.0f};
  /// Input: key fractions, non-decreasing.
  MFFloat key{*this, "key", ChangeKind::Parameter};
  /// Input: one value per key.
  MFVec3f keyValue{*this, "keyValue", ChangeKind::Parameter};
  /// Output: n points.
  MFVec3f value_changed{*this, "value_changed", ChangeKind::Parameter};

 protected:
  CoordinateInterpolator() = default;
};

}  // namespace tg::nodes
