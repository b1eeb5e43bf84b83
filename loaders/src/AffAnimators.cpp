#include "AffAnimators.h"

#include <cmath>

#include "tracegraph/nodes/Switch.h"
#include "tracegraph/scenegraph/Rotation.h"

namespace tg::aff {

ref_ptr<AffTrackAnimator> AffTrackAnimator::create(std::shared_ptr<const AffTrack> track,
                                                   double initial) {
  ref_ptr<AffTrackAnimator> a(new AffTrackAnimator(std::move(track)));
  a->setName(a->track_->name);
  a->evaluate(initial);
  return a;
}

void AffTrackAnimator::evaluate(double time) {
  // Outputs only: the scheduler copies them to the connected fields afterwards. Equal values
  // do not notify, so a track at rest leaves its transforms clean.
  matrix_changed.setValue(track_->evaluate(time));
  if (!track_->visibility.empty())
    whichChild_changed.setValue(track_->visibleAt(time) ? nodes::Switch::kAll
                                                        : nodes::Switch::kNone);
  if (track_->translation) translation_changed.setValue(Vec3f(track_->translation->evaluate(time)));
}

ref_ptr<AffCameraAnimator> AffCameraAnimator::create(std::shared_ptr<const AffTrack> track,
                                                     const AffView& view, double initial) {
  ref_ptr<AffCameraAnimator> a(new AffCameraAnimator(std::move(track), view));
  a->setName("camera");
  a->evaluate(initial);
  return a;
}

void AffCameraAnimator::evaluate(double time) {
  // Same channels and fallbacks as AffDocument::camera(t).
  const AffTrack* t = track_.get();
  const Vec3d eye = t && t->translation ? t->translation->evaluate(time) : view_.from;
  Rotation r;
  if (t && t->rotation) {
    // The track's quaternion is the camera's orientation itself: its matrix maps −Z to the
    // view direction and +Y to up, exactly as the reference builds the view.
    const Quatd q = t->rotation->evaluate(time);
    r = toRotation(Quaternion{q.w, q.x, q.y, q.z});
  } else {
    r = viewRotation(view_.at - view_.from, view_.up);
  }
  position_changed.setValue(Vec3f(eye));
  orientation_changed.setValue(r);
}

Rotation viewRotation(const Vec3d& direction, const Vec3d& up) {
  const double dl = length(direction);
  if (!(dl > 0.0) || !isFinite(direction) || !isFinite(up)) return Rotation{};
  const Vec3d back = -direction / dl;  // the camera's +Z points away from the view
  Vec3d right = cross(up, back);
  const double rl = length(right);
  if (!(rl > 0.0)) return Rotation{};
  right = right / rl;
  return toRotation(quaternionFromBasis(right, cross(back, right), back));
}

}  // namespace tg::aff
