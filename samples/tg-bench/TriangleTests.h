/// @file TriangleTests.h
/// Ray/triangle tests compared by the accuracy suite: Tracegraph's watertight test and, for
/// the bench only, Moller-Trumbore in float and in double. They are never used for rendering;
/// they exist to show what the watertight test buys (no leaks) and what it costs (speed).
#pragma once

#include <string>
#include <vector>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/WatertightTriangle.h"

namespace tg::bench {

/// A ray with the per-ray constants every test needs, computed once.
struct PreparedRay {
  Ray ray;
  WatertightRay wt;
  explicit PreparedRay(const Ray& r) : ray(r), wt(r.origin, r.direction, r.tnear) {}
};

/// Tests triangle (a, b, c) for t in [tnear, tfar]; on a hit writes t and returns true.
using TriangleTestFn = bool (*)(const PreparedRay& r, const Vec3f& a, const Vec3f& b,
                                const Vec3f& c, float tfar, float& t);

inline bool watertightTest(const PreparedRay& r, const Vec3f& a, const Vec3f& b, const Vec3f& c,
                           float tfar, float& t) {
  TriangleHit h;
  if (!intersectWatertight(r.wt, a, b, c, tfar, h)) return false;
  t = h.t;
  return true;
}

/// Moller and Trumbore (1997) without any epsilon: edges inclusive, a zero determinant rejects.
template <typename T>
bool mollerTrumbore(const PreparedRay& r, const Vec3f& a, const Vec3f& b, const Vec3f& c,
                    float tfar, float& tOut) {
  using V = Vec3<T>;
  const V o(r.ray.origin), d(r.ray.direction), va(a);
  const V e1 = V(b) - va, e2 = V(c) - va;
  const V p = cross(d, e2);
  const T det = dot(e1, p);
  if (det == T(0)) return false;
  const T inv = T(1) / det;
  const V s = o - va;
  const T u = dot(s, p) * inv;
  if (u < T(0) || u > T(1)) return false;
  const V q = cross(s, e1);
  const T v = dot(d, q) * inv;
  if (v < T(0) || u + v > T(1)) return false;
  const T t = dot(e2, q) * inv;
  if (!(t >= T(r.ray.tnear) && t <= T(tfar))) return false;
  tOut = static_cast<float>(t);
  return true;
}

struct TriangleTestVariant {
  std::string name;
  TriangleTestFn test;
};

/// The triangle tests compared, Tracegraph's first.
inline std::vector<TriangleTestVariant> triangleTestVariants() {
  return {{"watertight", &watertightTest},
          {"moller-trumbore-f32", &mollerTrumbore<float>},
          {"moller-trumbore-f64", &mollerTrumbore<double>}};
}

}  // namespace tg::bench
