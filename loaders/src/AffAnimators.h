// Animators that drive the nodes built from an AFF document: one per keyframe track (`k`)
// and one for the camera.
#pragma once

#include <memory>

#include "tracegraph/loaders/AffDocument.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::aff {

/// Evaluates one AFF keyframe track at the clock time. Every `x name` block of that name
/// connects its MatrixTransform's `matrix` from `matrix_changed`; a block whose track has a
/// visibility channel connects a Switch's `whichChild` from `whichChild_changed`; `la` lights
/// connect their location from `translation_changed`.
class AffTrackAnimator : public Animator {
 public:
  /// An animator for `track` (shared, never null), with outputs already at time `initial`.
  static ref_ptr<AffTrackAnimator> create(std::shared_ptr<const AffTrack> track, double initial);
  std::string_view className() const override { return "AffTrackAnimator"; }
  void evaluate(double time) override;
  /// The track evaluated.
  const AffTrack& track() const { return *track_; }

  /// Output: M(t) = T(t)·R(t)·S(t).
  SFMatrix matrix_changed{*this, "matrix_changed", ChangeKind::Parameter};
  /// Output: Switch::kAll while visible, Switch::kNone while hidden.
  SFInt32 whichChild_changed{*this, "whichChild_changed", ChangeKind::Parameter, -3};
  /// Output: the translation channel (the origin when the track has none).
  SFVec3f translation_changed{*this, "translation_changed", ChangeKind::Parameter};

 private:
  explicit AffTrackAnimator(std::shared_ptr<const AffTrack> track) : track_(std::move(track)) {}
  std::shared_ptr<const AffTrack> track_;
};

/// Poses the camera as AffDocument::camera(t) does: eye from the `camera` track's translation,
/// orientation from its rotation (the default view looks along −Z with +Y up, so R maps it to
/// direction R·(0,0,−1) and up R·(0,1,0)); a missing channel falls back to the `v` command.
class AffCameraAnimator : public Animator {
 public:
  /// An animator for the camera track (null: `v` only) and view, outputs at time `initial`.
  static ref_ptr<AffCameraAnimator> create(std::shared_ptr<const AffTrack> track,
                                           const AffView& view, double initial);
  std::string_view className() const override { return "AffCameraAnimator"; }
  void evaluate(double time) override;

  /// Output: eye position.
  SFVec3f position_changed{*this, "position_changed", ChangeKind::Parameter};
  /// Output: rotation of the default view frame.
  SFRotation orientation_changed{*this, "orientation_changed", ChangeKind::Parameter};

 private:
  AffCameraAnimator(std::shared_ptr<const AffTrack> track, const AffView& view)
      : track_(std::move(track)), view_(view) {}
  std::shared_ptr<const AffTrack> track_;
  AffView view_;
};

/// The rotation taking the default camera frame (looking along −Z, +Y up) to one looking
/// along `direction` with `up` roughly up; the identity for degenerate input.
Rotation viewRotation(const Vec3d& direction, const Vec3d& up);

}  // namespace tg::aff
