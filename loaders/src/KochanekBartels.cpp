#include "tracegraph/loaders/KochanekBartels.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <utility>

#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

// The reference's threshold for "these quaternions are (anti)parallel": below it slerp, log and
// exp switch to their first-order forms. Keeping the same value keeps frames comparable.
constexpr double kCutoff = 1e-3;

constexpr double kDegToRad = std::numbers::pi / 180.0;

constexpr Quatd operator*(double s, const Quatd& q) {
  return {s * q.w, s * q.x, s * q.y, s * q.z};
}
constexpr Quatd operator+(const Quatd& a, const Quatd& b) {
  return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
}

/// Where time t falls on a key list: hold key 1, hold key n-2, or segment s (from key s).
struct SegmentChoice {
  enum Kind { kHoldFirst, kHoldLast, kSegment } kind;
  std::size_t segment;
};

/// The reference search: t ≤ t1 holds key 1, t ≥ t(n-2) holds key n-2, otherwise the first
/// segment in key order whose end time exceeds t. Because the previous segment's end (or t1)
/// was not greater than t, the chosen segment always has t(i) ≤ t < t(j), hence a positive
/// length, even for the non-monotonic lists in the data.
template <typename KeyT>
SegmentChoice findSegment(const std::vector<KeyT>& keys, double t) {
  const std::size_t n = keys.size();
  if (!(t > keys[1].time)) return {SegmentChoice::kHoldFirst, 0};
  if (t >= keys[n - 2].time) return {SegmentChoice::kHoldLast, 0};
  for (std::size_t s = 1; s + 2 < n; ++s) {
    if (keys[s + 1].time > t) return {SegmentChoice::kSegment, s};
  }
  return {SegmentChoice::kHoldLast, 0};  // unreachable for finite t; kept for safety
}

/// Time-spacing factors f_i = h/(t_j - t_{i-1}) and f_j = h/(t_{j+1} - t_i) of segment s. For
/// ordered keys the denominators are at least h; the max() only matters for segments of
/// non-monotonic lists, where it avoids division by zero or a sign change (f is then 1).
template <typename KeyT>
std::pair<double, double> spacingFactors(const std::vector<KeyT>& k, std::size_t s) {
  const double h = k[s + 1].time - k[s].time;
  const double fi = h / std::max(k[s + 1].time - k[s - 1].time, h);
  const double fj = h / std::max(k[s + 2].time - k[s].time, h);
  return {fi, fj};
}

template <typename KeyT>
void requireKeys(const std::vector<KeyT>& keys, const char* what) {
  if (keys.size() < 4) {
    throw Error(std::string(what) + ": a Kochanek-Bartels channel needs at least 4 keys, got " +
                std::to_string(keys.size()));
  }
}

bool finite(const Vec3d& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(const KbParams& p) {
  return std::isfinite(p.tension) && std::isfinite(p.continuity) && std::isfinite(p.bias);
}

}  // namespace

Quatd Quatd::fromAxisAngle(const Vec3d& axis, double radians) {
  const double len = length(axis);
  if (!(len > 0.0)) return {};
  const double half = 0.5 * radians;
  const double s = std::sin(half) / len;
  return {std::cos(half), axis.x * s, axis.y * s, axis.z * s};
}

Affine3d Quatd::toMatrix() const {
  const double angle = 2.0 * std::acos(std::clamp(w, -1.0, 1.0));
  return rotationMatrix(vec(), angle);
}

Vec3d quatLog(const Quatd& q) {
  const Vec3d v = q.vec();
  const double s = length(v);  // sin φ for a unit quaternion
  if (s < kCutoff) return v;
  const double phi = std::atan2(s, q.w);
  return v * (phi / s);
}

Quatd quatExp(const Vec3d& v) {
  const double theta = length(v);
  if (theta < kCutoff) return {std::cos(theta), v.x, v.y, v.z};
  const double s = std::sin(theta) / theta;
  return {std::cos(theta), v.x * s, v.y * s, v.z * s};
}

Quatd slerpNoFlip(const Quatd& a, const Quatd& b, double u) {
  const double c = std::clamp(a.dot(b), -1.0, 1.0);
  const double omega = std::acos(c);
  const double s = std::sin(omega);
  if (s < kCutoff) return a;
  // At u = 0 both sines take the same argument, so the first weight is exactly 1 and the
  // result is exactly `a`: keys are hit without rounding error.
  return (std::sin((1.0 - u) * omega) / s) * a + (std::sin(u * omega) / s) * b;
}

Affine3d rotationMatrix(const Vec3d& axis, double radians) {
  return Affine3d::rotationRadians(axis, radians);
}

KbVectorSpline::KbVectorSpline(std::vector<Key> keys) : keys_(std::move(keys)) {
  requireKeys(keys_, "KbVectorSpline");
  for (const Key& k : keys_) {
    if (!std::isfinite(k.time) || !finite(k.value) || !finite(k.tcb))
      throw Error("KbVectorSpline: key holds a non-finite number");
  }
}

Vec3d KbVectorSpline::evaluate(double t) const {
  const SegmentChoice c = findSegment(keys_, t);
  if (c.kind == SegmentChoice::kHoldFirst) return keys_[1].value;
  if (c.kind == SegmentChoice::kHoldLast) return keys_[keys_.size() - 2].value;
  const std::size_t i = c.segment, j = i + 1;
  const Key& ki = keys_[i];
  const Key& kj = keys_[j];
  const auto [fi, fj] = spacingFactors(keys_, i);
  const Vec3d d = kj.value - ki.value;
  const KbParams& pi = ki.tcb;
  const KbParams& pj = kj.tcb;
  const Vec3d out = ((ki.value - keys_[i - 1].value) * ((1 + pi.continuity) * (1 + pi.bias)) +
                     d * ((1 - pi.continuity) * (1 - pi.bias))) *
                    (fi * (1 - pi.tension));
  const Vec3d in = (d * ((1 - pj.continuity) * (1 + pj.bias)) +
                    (keys_[j + 1].value - kj.value) * ((1 + pj.continuity) * (1 - pj.bias))) *
                   (fj * (1 - pj.tension));
  const double u = (t - ki.time) / (kj.time - ki.time);
  // Hermite form of the cubic with P(0) = Pi, P(1) = Pj, P'(0) = out, P'(1) = in.
  return ki.value + out * u + (d * 3.0 - out * 2.0 - in) * (u * u) +
         (out + in - d * 2.0) * (u * u * u);
}

KbRotationSpline::KbRotationSpline(std::vector<Key> keys) : keys_(std::move(keys)) {
  requireKeys(keys_, "KbRotationSpline");
  for (const Key& k : keys_) {
    if (!std::isfinite(k.time) || !finite(k.axis) || !std::isfinite(k.degrees) || !finite(k.tcb))
      throw Error("KbRotationSpline: key holds a non-finite number");
  }
  const std::size_t n = keys_.size();
  q_.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    q_[k] = Quatd::fromAxisAngle(keys_[k].axis, keys_[k].degrees * kDegToRad);
  inner_.assign(2 * n, Quatd{});
  // Segments in increasing order, each flipping its end key when needed before its tangents
  // are built; q_[j + 1] is therefore still in its original sign here (reference behaviour).
  for (std::size_t i = 1; i + 2 < n; ++i) {
    const std::size_t j = i + 1;
    if (q_[i].dot(q_[j]) < 0.0) q_[j] = -q_[j];
    const KbParams& pi = keys_[i].tcb;
    const KbParams& pj = keys_[j].tcb;
    const auto [fi, fj] = spacingFactors(keys_, i);
    const Vec3d l = quatLog(q_[i].conjugate() * q_[j]);
    const Vec3d prev = quatLog(q_[i - 1].conjugate() * q_[i]);
    const Vec3d next = quatLog(q_[j].conjugate() * q_[j + 1]);
    const Vec3d out =
        (prev * ((1 + pi.continuity) * (1 + pi.bias)) + l * ((1 - pi.continuity) * (1 - pi.bias))) *
        (fi * (1 - pi.tension));
    const Vec3d in =
        (l * ((1 - pj.continuity) * (1 + pj.bias)) + next * ((1 + pj.continuity) * (1 - pj.bias))) *
        (fj * (1 - pj.tension));
    inner_[2 * i] = q_[i] * quatExp((out - l) * 0.5);
    inner_[2 * i + 1] = q_[j] * quatExp((l - in) * 0.5);
  }
}

Quatd KbRotationSpline::evaluate(double t) const {
  const SegmentChoice c = findSegment(keys_, t);
  if (c.kind == SegmentChoice::kHoldFirst) return q_[1];
  if (c.kind == SegmentChoice::kHoldLast) return q_[keys_.size() - 2];
  const std::size_t i = c.segment, j = i + 1;
  const double u = (t - keys_[i].time) / (keys_[j].time - keys_[i].time);
  return slerpNoFlip(slerpNoFlip(q_[i], q_[j], u), slerpNoFlip(inner_[2 * i], inner_[2 * i + 1], u),
                     2.0 * u * (1.0 - u));
}

bool evaluateVisibility(const std::vector<VisibilityKey>& keys, double t) {
  bool visible = true;
  for (const VisibilityKey& k : keys) {
    if (k.time <= t) visible = k.visible;
  }
  return visible;
}

}  // namespace tg
