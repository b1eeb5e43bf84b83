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
  const Vec3d trueUp = cross(back, right);
  // Quaternion of the rotation matrix with columns right, trueUp, back (Shepperd's method:
  // divide by the largest of the four candidate terms for accuracy).
  const double m00 = right.x, m01 = trueUp.x, m02 = back.x;
  const double m10 = right.y, m11 = trueUp.y, m12 = back.y;
  const double m20 = right.z, m21 = trueUp.z, m22 = back.z;
  Quaternion q;
  const double trace = m00 + m11 + m22;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(trace + 1.0);
    q = {0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  } else if (m00 > m11 && m00 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
    q = {(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  } else if (m11 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
    q = {(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
    q = {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
  }
  return toRotation(q);
}

}  // namespace tg::aff
