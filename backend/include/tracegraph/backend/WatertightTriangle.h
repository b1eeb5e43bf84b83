/// @file WatertightTriangle.h
/// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013).
///
/// The ray is sheared so that it becomes the +z axis; the three 2D edge functions of the sheared
/// triangle then decide inside/outside. Neighbouring triangles evaluate the *same* edge function
/// for a shared edge (with opposite sign), so a ray through an edge or vertex can never slip
/// between them (hard case 1). When an edge function is exactly zero in float, it is recomputed
/// in double so that the sign on the edge is decided consistently (hard case 2).
#pragma once

#include <cmath>
#include <cstddef>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "tracegraph/backend/Ray.h"

namespace tg {

/// Per-ray constants of the watertight test, computed once per (object-space) ray.
struct WatertightRay {
  /// Origin (float).
  Vec3f origin;
  /// Direction (float, not normalised).
  Vec3f direction;
  /// The same ray in double: the world ray mapped by the instance's double inverse matrix. The
  /// inside test uses the float ray; t is refined on this one (see intersectWatertight).
  Vec3d originD;
  /// Direction in double (see originD).
  Vec3d directionD{0.0, 0.0, 1.0};
  /// Smallest t that counts.
  float tnear = 0.0f;
  ///@{
  int kx = 0, ky = 1, kz = 2;  ///< axis permutation: kz = dominant direction axis
  ///@}
  ///@{
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;  ///< shear constants
  ///@}

  /// The axis permutation for a direction whose dominant axis is `kz` (the first largest
  /// |component|): kx and ky follow kz cyclically, swapped when dir[kz] < 0 so that the sheared
  /// triangle keeps its winding whatever the ray's orientation. Packet mappings use it too.
  static void shearAxes(const Vec3f& dir, int kz, int& kx, int& ky) {
    shearAxes(kz, dir[kz] < 0.0f, kx, ky);
  }
  /// shearAxes for a direction whose dominant axis is `kz`, given only whether dir[kz] < 0.
  static void shearAxes(int kz, bool negative, int& kx, int& ky) {
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (negative) std::swap(kx, ky);
  }

  WatertightRay() = default;
  /// `direction` must be finite and non-zero (the scene rejects other rays before traversal).
  WatertightRay(const Vec3f& org, const Vec3f& dir, float tnear_)
      : WatertightRay(org, dir, Vec3d(org), Vec3d(dir), tnear_) {}
  /// From a double ray (object space of an instance); the float ray is its rounding.
  WatertightRay(const Vec3d& org, const Vec3d& dir, float tnear_)
      : WatertightRay(Vec3f(org), Vec3f(dir), org, dir, tnear_) {}

 private:
  WatertightRay(const Vec3f& org, const Vec3f& dir, const Vec3d& orgD, const Vec3d& dirD,
                float tnear_)
      : origin(org), direction(dir), originD(orgD), directionD(dirD), tnear(tnear_) {
    const Vec3f ad = abs(dir);
    kz = maxDimension(ad);
    shearAxes(dir, kz, kx, ky);
#if defined(__SSE2__)
    // The three quotients in one vector division: correctly rounded lane by lane, so the same
    // bits as three scalar ones, for a third of the divider's time (every ray makes one).
    alignas(16) float q[4];
    _mm_store_ps(q, _mm_div_ps(_mm_set_ps(1.0f, 1.0f, dir[ky], dir[kx]), _mm_set1_ps(dir[kz])));
    sx = q[0];
    sy = q[1];
    sz = q[2];
#else
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = 1.0f / dir[kz];
#endif
  }
};

/// Distance and barycentrics of a triangle hit.
struct TriangleHit {
  ///@{
  /// Distance along the ray and barycentrics of vertices b and c.
  float t = 0.0f, u = 0.0f, v = 0.0f;
  ///@}
  /// cross(b - a, c - a) in double, as computed for t: the unnormalised geometric normal, never
  /// zero for a hit.
  Vec3d normal;
};

namespace detail {

/// The axis permutation of a WatertightRay as run-time values.
struct RayAxes {
  std::size_t kx, ky, kz;
  explicit RayAxes(const WatertightRay& ray)
      : kx(static_cast<std::size_t>(ray.kx)),
        ky(static_cast<std::size_t>(ray.ky)),
        kz(static_cast<std::size_t>(ray.kz)) {}
};

/// An axis permutation as compile-time constants: the triangle test then reads the vertex
/// components it needs directly, where run-time indices make it select them one by one.
template <std::size_t Kx, std::size_t Ky, std::size_t Kz>
struct FixedAxes {
  static constexpr std::size_t kx = Kx, ky = Ky, kz = Kz;
};

/// The rest of the watertight test for a triangle (a, b, c) whose edge functions U, V, W
/// (sheared as intersectWatertightWith computes them, none exactly zero or already decided in
/// double) passed the inside test: rejects a zero determinant, refines t and checks it against
/// [ray.tnear, tfar]. A SIMD leaf test that computes U, V, W lane by lane with the same
/// operations gives the same answers through it as the scalar test.
[[gnu::always_inline]] inline bool finishWatertight(const WatertightRay& ray, const Vec3f& a,
                                                    const Vec3f& b, const Vec3f& c, float U,
                                                    float V, float W, float tfar,
                                                    TriangleHit& out) {
  const float det = U + V + W;
  if (det == 0.0f) return false;
  // The inside test before this is what must be watertight; t only needs to be accurate. Woop's
  // T / det is a weighted average whose weights lose relative precision near edges, which
  // costs tens of ulps on small, distant triangles. A candidate that passed the inside test is
  // rare (a few per ray), so its plane distance is recomputed in double from the original
  // vertices and the double ray: t = n.(a - o) / n.d, accurate to about one ulp except at
  // grazing incidence, also through instances (the float object-space origin alone would carry
  // an error of the size of its own magnitude's ulp; hard case 7).
  const Vec3d da(a);
  const Vec3d& o = ray.originD;
  const Vec3d& d = ray.directionD;
  const Vec3d n = cross(Vec3d(b) - da, Vec3d(c) - da);
  const double nd = dot(n, d);
  if (nd == 0.0) return false;  // ray in the triangle's plane: never a hit
  const auto t = static_cast<float>(dot(n, da - o) / nd);
  // Also rejects NaN, and t overflowing to infinity.
  if (!(t >= ray.tnear && t <= tfar && t < kInfinity)) return false;
  const float invDet = 1.0f / det;
  out.t = t;
  out.u = V * invDet;
  out.v = W * invDet;
  out.normal = n;
  return true;
}

/// intersectWatertight with the ray's permutation given as `axes` (RayAxes or the FixedAxes
/// equal to it): the same operations in the same order, so the same answers.
template <class Axes>
inline bool intersectWatertightWith(const WatertightRay& ray, const Axes& axes, const Vec3f& a,
                                    const Vec3f& b, const Vec3f& c, float tfar, TriangleHit& out) {
  const Vec3f A = a - ray.origin;
  const Vec3f B = b - ray.origin;
  const Vec3f C = c - ray.origin;
  const float ax = A[axes.kx] - ray.sx * A[axes.kz];
  const float ay = A[axes.ky] - ray.sy * A[axes.kz];
  const float bx = B[axes.kx] - ray.sx * B[axes.kz];
  const float by = B[axes.ky] - ray.sy * B[axes.kz];
  const float cx = C[axes.kx] - ray.sx * C[axes.kz];
  const float cy = C[axes.ky] - ray.sy * C[axes.kz];
  float U = cx * by - cy * bx;
  float V = ax * cy - ay * cx;
  float W = bx * ay - by * ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
    // Exactly on an edge in float: decide in double, where these products are exact.
    const double cxby = double(cx) * double(by), cybx = double(cy) * double(bx);
    const double axcy = double(ax) * double(cy), aycx = double(ay) * double(cx);
    const double bxay = double(bx) * double(ay), byax = double(by) * double(ax);
    U = static_cast<float>(cxby - cybx);
    V = static_cast<float>(axcy - aycx);
    W = static_cast<float>(bxay - byax);
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  return finishWatertight(ray, a, b, c, U, V, W, tfar, out);
}

}  // namespace detail

/// Tests the triangle (a, b, c) against the ray for t in [ray.tnear, tfar]. Degenerate
/// triangles (zero determinant) never hit. Both faces are hit (no culling).
inline bool intersectWatertight(const WatertightRay& ray, const Vec3f& a, const Vec3f& b,
                                const Vec3f& c, float tfar, TriangleHit& out) {
  return detail::intersectWatertightWith(ray, detail::RayAxes(ray), a, b, c, tfar, out);
}

}  // namespace tg
