/// @file GraphTestUtil.h
/// Small graph builders and ray helpers shared by the scenegraph and nodes tests.
#pragma once

#include <cmath>
#include <ostream>
#include <random>
#include <vector>

#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/Transform.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace tg {

// Printers so that Boost.Test can show the values of failed comparisons.
inline std::ostream& operator<<(std::ostream& os, DynamicsClass c) {
  return os << dynamicsClassName(c);
}
inline std::ostream& operator<<(std::ostream& os, ChangeKind k) {
  return os << toString(k);
}
inline std::ostream& operator<<(std::ostream& os, const Vec3f& v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}
inline std::ostream& operator<<(std::ostream& os, ObjectUsage u) {
  return os << static_cast<int>(u);
}
inline std::ostream& operator<<(std::ostream& os, const Affine3d& m) {
  os << '[';
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) os << m.m[r][c] << (c == 3 ? (r == 2 ? "]" : "; ") : " ");
  return os;
}

}  // namespace tg

namespace tgtest {

/// An axis-aligned box as 12 outward-facing triangles.
inline tg::ref_ptr<tg::nodes::Mesh> makeBox(const tg::Vec3f& lo, const tg::Vec3f& hi) {
  std::vector<tg::Vec3f> p;
  for (int i = 0; i < 8; ++i)
    p.emplace_back((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
  std::vector<std::int32_t> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return tg::nodes::Mesh::create(std::move(p), std::move(idx));
}

/// A unit box around the origin.
inline tg::ref_ptr<tg::nodes::Mesh> unitBox() {
  return makeBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
}

/// A transform with a translation.
inline tg::ref_ptr<tg::nodes::Transform> translate(const tg::Vec3f& t) {
  tg::ref_ptr<tg::nodes::Transform> x = tg::nodes::Transform::create();
  x->translation.setValue(t);
  return x;
}

/// A separator holding the given children.
template <typename... Children>
tg::ref_ptr<tg::nodes::Separator> sep(Children... children) {
  tg::ref_ptr<tg::nodes::Separator> s = tg::nodes::Separator::create();
  (s->addChild(children), ...);
  return s;
}

/// The hit of a ray in a scene, or an invalid hit.
inline tg::Hit trace(const tg::Scene& scene, const tg::Ray& ray) {
  tg::Hit h;
  scene.intersect(ray, h);
  return h;
}

/// A ray from `o` towards `target`.
inline tg::Ray rayTo(const tg::Vec3f& o, const tg::Vec3f& target) {
  tg::Ray r;
  r.origin = o;
  r.direction = target - o;
  return r;
}

/// What a ray hits in graph terms.
struct MappedHit {
  bool hit = false;
  float t = 0.0f;
  const tg::ShapeNode* shape = nullptr;
  std::uint32_t triangle = 0;
  const tg::MaterialNode* material = nullptr;
  float u = 0.0f, v = 0.0f;
};

/// Traces a ray through a synced SceneGraph and maps the hit back to its mesh node.
inline MappedHit traceMapped(const tg::SceneGraph& sg, const tg::Ray& ray) {
  MappedHit m;
  const tg::Hit h = trace(sg.backendScene(), ray);
  if (!h.valid()) return m;
  const tg::HitInfo info = sg.hitInfo(h);
  m.hit = true;
  m.t = h.t;
  m.shape = info.shape;
  m.triangle = info.triangle;
  m.material = info.material;
  m.u = h.u;
  m.v = h.v;
  return m;
}

/// Rays from random points on a sphere of radius `radius` around `center` towards random
/// points of the cube of half-size `spread` around it.
inline std::vector<tg::Ray> randomRays(std::mt19937& rng, const tg::Vec3f& center, float radius,
                                       float spread, std::size_t count) {
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::uniform_real_distribution<float> uni(-spread, spread);
  std::vector<tg::Ray> rays;
  rays.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    tg::Vec3f d(normal(rng), normal(rng), normal(rng));
    d = tg::normalize(d);
    const tg::Vec3f o = center + d * radius;
    const tg::Vec3f target = center + tg::Vec3f(uni(rng), uni(rng), uni(rng));
    rays.push_back(rayTo(o, target));
  }
  return rays;
}

}  // namespace tgtest
