// Test geometry and the differential check against the double-precision reference, shared by
// the backend test suites.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tracegraph/backend/ReferenceIntersector.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/TriangleMesh.h"

namespace tg::test {

/// Axis-aligned box [lo, hi] as 12 outward-facing (counter-clockwise) triangles.
inline TriangleMesh makeBox(const Vec3f& lo = {0, 0, 0}, const Vec3f& hi = {1, 1, 1}) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  }
  return m;
}

/// Icosphere of radius 1 with 20 * 4^level triangles, vertices shared between triangles.
inline TriangleMesh makeIcosphere(int level) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> v = {{-1, phi, 0}, {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0},
                          {0, -1, phi}, {0, 1, phi},  {0, -1, -phi}, {0, 1, -phi},
                          {phi, 0, -1}, {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  for (Vec3d& p : v) p = normalize(p);
  std::vector<std::uint32_t> f = {0, 11, 5, 0, 5,  1,  0,  1, 7, 0, 7,  10, 0, 10, 11,
                                  1, 5,  9, 5, 11, 4,  11, 10, 2, 10, 7, 6, 7, 1,  8,
                                  3, 9,  4, 3, 4,  2,  3,  2, 6, 3, 6,  8,  3, 8,  9,
                                  4, 9,  5, 2, 4,  11, 6,  2, 10, 8, 6, 7, 9, 8,  1};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      v.push_back(normalize((v[a] + v[b]) * 0.5));
      const auto id = static_cast<std::uint32_t>(v.size() - 1);
      midpoints.emplace(key, id);
      return id;
    };
    std::vector<std::uint32_t> next;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(next);
  }
  TriangleMesh m;
  for (const Vec3d& p : v) m.positions.push_back(Vec3f(p));
  m.indices = std::move(f);
  return m;
}

/// Torus around the z axis with shared vertices.
inline TriangleMesh makeTorus(double major, double minor, int segments, int rings) {
  TriangleMesh m;
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * std::numbers::pi * i / segments;
    for (int j = 0; j < rings; ++j) {
      const double b = 2.0 * std::numbers::pi * j / rings;
      const double r = major + minor * std::cos(b);
      m.positions.push_back(Vec3f(Vec3d(r * std::cos(a), r * std::sin(a), minor * std::sin(b))));
    }
  }
  auto id = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % segments) * rings + (j % rings));
  };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < rings; ++j)
      m.indices.insert(m.indices.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j),
                                         id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

/// n random triangles with vertices in [lo, hi]^3 and edges up to `size`.
inline TriangleMesh makeRandomTriangles(std::mt19937& rng, std::size_t n, float lo, float hi,
                                        float size) {
  std::uniform_real_distribution<float> pos(lo, hi), off(-size, size);
  TriangleMesh m;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f c{pos(rng), pos(rng), pos(rng)};
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + Vec3f{off(rng), off(rng), off(rng)});
      m.indices.push_back(static_cast<std::uint32_t>(m.positions.size() - 1));
    }
  }
  return m;
}

/// A random rigid-ish transform: rotation, scale in [0.3, 2] per axis (optionally mirrored),
/// translation within `spread`.
inline Affine3d randomTransform(std::mt19937& rng, double spread, bool allowMirror) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), s(0.3, 2.0);
  Vec3d scale{s(rng), s(rng), s(rng)};
  if (allowMirror && u(rng) < -0.5) scale.x = -scale.x;
  return Affine3d::translation({u(rng) * spread, u(rng) * spread, u(rng) * spread}) *
         Affine3d::rotation({u(rng), u(rng), u(rng) + 0.01}, u(rng) * 180.0) *
         Affine3d::scaling(scale);
}

/// Rays of several kinds through a box: random, axis-parallel (with +-0 components), aimed at
/// the given points (vertices, edge points).
inline std::vector<Ray> makeRays(std::mt19937& rng, const Box3f& box, std::size_t count,
                                 const std::vector<Vec3f>& targets = {}) {
  std::vector<Ray> rays;
  rays.reserve(count);
  const Vec3f c = box.center(), e = box.extent();
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> kind(0, targets.empty() ? 2 : 3), axis(0, 2), sign(0, 1);
  std::uniform_int_distribution<std::size_t> pick(0, targets.empty() ? 0 : targets.size() - 1);
  for (std::size_t i = 0; i < count; ++i) {
    Ray r;
    const Vec3f inside = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.5f;
    switch (kind(rng)) {
      case 0:  // random origin inside or around the box, random direction
        r.origin = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        r.direction = {u(rng), u(rng), u(rng)};
        break;
      case 1: {  // axis-parallel from outside, remaining components +0 or -0
        const int a = axis(rng);
        r.origin = inside;
        r.origin[a] = sign(rng) ? box.upper[a] + e[a] : box.lower[a] - e[a];
        r.direction = {sign(rng) ? 0.0f : -0.0f, sign(rng) ? 0.0f : -0.0f,
                       sign(rng) ? 0.0f : -0.0f};
        r.direction[a] = r.origin[a] > c[a] ? -1.0f : 1.0f;
        break;
      }
      case 2:  // from far outside towards a point inside
        r.origin = c + Vec3f{u(rng), u(rng), u(rng)} * (2.0f * maxComponent(e) + 1.0f);
        r.direction = inside - r.origin;
        break;
      default:  // aimed exactly at a target point
        r.origin = c + Vec3f{u(rng), u(rng), u(rng)} * (2.0f * maxComponent(e) + 1.0f);
        r.direction = targets[pick(rng)] - r.origin;
        break;
    }
    if (r.direction == Vec3f{0, 0, 0}) r.direction = {0, 0, 1};
    rays.push_back(r);
  }
  return rays;
}

/// Counts of a differential run.
struct DiffResult {
  std::size_t rays = 0, hits = 0, ambiguous = 0, mismatches = 0;
  std::string firstMismatch;
};

/// True when `a` and `b` have the same bits (-0 and +0 differ, as do NaN payloads).
inline bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
/// sameBits for doubles.
inline bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// True when two hits agree bit for bit in every field.
inline bool sameHitBits(const Hit& a, const Hit& b) {
  return sameBits(a.t, b.t) && sameBits(a.u, b.u) && sameBits(a.v, b.v) &&
         a.instanceId == b.instanceId && a.objectId == b.objectId && a.primId == b.primId &&
         sameBits(a.geometricNormal.x, b.geometricNormal.x) &&
         sameBits(a.geometricNormal.y, b.geometricNormal.y) &&
         sameBits(a.geometricNormal.z, b.geometricNormal.z);
}

inline std::string describe(const Ray& r) {
  std::ostringstream s;
  s.precision(9);
  s << "org (" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z << ") dir ("
    << r.direction.x << ", " << r.direction.y << ", " << r.direction.z << ") [" << r.tnear
    << ", " << r.tfar << "]";
  return s.str();
}

/// Compares closest hit and occlusion of `scene` with the reference on every ray.
inline DiffResult compareWithReference(const Scene& scene, const ReferenceIntersector& ref,
                                       const std::vector<Ray>& rays) {
  DiffResult out;
  auto fail = [&](const Ray& r, const std::string& what) {
    ++out.mismatches;
    if (out.firstMismatch.empty()) out.firstMismatch = what + " for ray " + describe(r);
  };
  for (const Ray& r : rays) {
    ++out.rays;
    const ReferenceHit expected = ref.intersect(r);
    Hit hit;
    const bool got = scene.intersect(r, hit);
    if (expected.hitAmbiguous) {
      ++out.ambiguous;
    } else if (got != expected.hit) {
      fail(r, got ? "hit where the reference misses" : "miss where the reference hits");
      continue;
    }
    if (got && expected.hit && !expected.hitAmbiguous) {
      ++out.hits;
      const double tol = 8.0 * ReferenceIntersector::tolerance(r, expected.t);
      if (std::abs(double(hit.t) - expected.t) > tol) {
        fail(r, "t " + std::to_string(hit.t) + " vs reference " + std::to_string(expected.t));
        continue;
      }
      if (hit.instanceId != expected.instanceId || hit.primId != expected.primId) {
        // Acceptable only when the reported triangle is itself hit at (nearly) the same t.
        const auto alt = ref.intersectTriangle(r, hit.instanceId, hit.primId);
        if (!expected.primAmbiguous || !alt || std::abs(*alt - expected.t) > tol)
          fail(r, "triangle (" + std::to_string(hit.instanceId) + ", " +
                      std::to_string(hit.primId) + ") vs reference (" +
                      std::to_string(expected.instanceId) + ", " +
                      std::to_string(expected.primId) + ")");
      }
    }
    bool occlusionAmbiguous = false;
    const bool expectedOccluded = ref.occluded(r, &occlusionAmbiguous);
    if (!occlusionAmbiguous && scene.occluded(r) != expectedOccluded)
      fail(r, expectedOccluded ? "not occluded where the reference is" : "occluded wrongly");
  }
  return out;
}

}  // namespace tg::test
