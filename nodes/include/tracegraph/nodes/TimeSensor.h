/// @file TimeSensor.h
/// Turns clock time into a fraction of a cycle, the usual input of interpolators.
#pragma once

#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// VRML TimeSensor: `fraction_changed` runs from 0 to 1 over `cycleInterval` seconds from
/// `startTime`, once or looping. Connect interpolators' `set_fraction` from it.
class TimeSensor : public Animator {
 public:
  /// A new sensor with a one-second cycle starting at time 0.
  static ref_ptr<TimeSensor> create() { return ref_ptr<TimeSensor>(new TimeSensor()); }
  std::string_view className() const override { return "TimeSensor"; }
  void evaluate(double time) override;

  /// Seconds per cycle.
  SFTime cycleInterval{*this, "cycleInterval", ChangeKind::Parameter, 1.0};
  /// Repeat instead of holding the last value.
  SFBool loop{*this, "loop", ChangeKind::Parameter, false};
  /// Clock time at which the first cycle starts.
  SFTime startTime{*this, "startTime", ChangeKind::Parameter, 0.0};
  /// False freezes the outputs.
  SFBool enabled{*this, "enabled", ChangeKind::Parameter, true};
  /// Output: fraction of the current cycle in [0, 1].
  SFFloat fraction_changed{*this, "fraction_changed", ChangeKind::Parameter, 0.0f};
  /// Output: the time of the last evaluation.
  SFTime time{*this, "time", ChangeKind::Parameter, 0.0};

 protected:
  TimeSensor() = default;
};

}  // namespace tg::nodes
