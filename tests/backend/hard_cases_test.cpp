// The intersection and top-level cases of ../shared/docs/hard-cases.md (1-12 and 18), for
// both object accelerators.
#define BOOST_TEST_MODULE hard_cases
#include <boost/test/unit_test.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>

#include "IntervalChecks.h"
#include "TestGeometry.h"
#include "tracegraph/backend/Error.h"

using namespace tg;
using namespace tg::test;

namespace {

constexpr AccelKind kKinds[] = {AccelKind::SahKdTree, AccelKind::FastKdTree, AccelKind::Bvh,
                                AccelKind::BvhFast};

/// Every object accelerator under the top level of its own engine.
SceneOptions optionsFor(AccelKind kind) {
  const bool kd = kind == AccelKind::SahKdTree || kind == AccelKind::FastKdTree;
  SceneOptions o = sceneOptionsFor(kd ? Engine::KdTree : Engine::Bvh);
  o.staticAccel = kind;
  o.deformingAccel = kind;
  return o;
}

/// Rays from `origin` aimed exactly at every vertex and at edge points (barycentric 0/1 in
/// float) of a closed mesh; returns how many missed.
std::size_t countLeaks(const Scene& scene, const TriangleMesh& mesh, const Vec3f& origin,
                       std::size_t& rays) {
  std::size_t leaks = 0;
  auto shoot = [&](const Vec3f& target) {
    Ray r;
    r.origin = origin;
    r.direction = target - origin;
    ++rays;
    Hit hit;
    if (!scene.intersect(r, hit)) ++leaks;
  };
  for (const Vec3f& v : mesh.positions) shoot(v);
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    for (int e = 0; e < 3; ++e) {
      const Vec3f a = mesh.positions[mesh.indices[i + e]];
      const Vec3f b = mesh.positions[mesh.indices[i + (e + 1) % 3]];
      shoot((a + b) * 0.5f);
      shoot(a + (b - a) * 0.25f);
    }
  }
  return leaks;
}

}  // namespace

BOOST_AUTO_TEST_CASE(case01_closed_meshes_do_not_leak) {
  const TriangleMesh meshes[] = {makeIcosphere(5), makeBox({-1, -1, -1}, {1, 1, 1}),
                                 makeTorus(2.0, 0.7, 48, 24)};
  const Vec3f origins[] = {{0.01f, -0.02f, 0.03f}, {0.1f, 0.2f, -0.3f}, {2.0f, 0.0f, 0.1f}};
  BOOST_TEST(meshes[0].triangleCount() >= 20000u);
  for (AccelKind kind : kKinds) {
    for (int m = 0; m < 3; ++m) {
      Scene scene(optionsFor(kind));
      scene.createInstance(scene.createObject(meshes[m]));
      scene.commit();
      std::size_t rays = 0;
      const std::size_t leaks = countLeaks(scene, meshes[m], origins[m], rays);
      BOOST_TEST_MESSAGE(accelKindName(kind)
                         << " mesh " << m << ": " << leaks << " leaks in " << rays << " rays");
      BOOST_TEST(leaks == 0u);
    }
  }
}

BOOST_AUTO_TEST_CASE(case02_shared_edge_decides_once_and_the_same_way) {
  const TriangleMesh mesh = makeIcosphere(3);
  Scene scene;
  scene.createInstance(scene.createObject(mesh));
  scene.commit();
  std::vector<Ray> rays;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3f a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]];
    rays.push_back({{0.0f, 0.0f, 0.0f}, 0.0f, (a + b) * 0.5f, kInfinity});
  }
  auto trace = [&](int threads) {
    std::vector<std::uint32_t> prims(rays.size());
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::parallel_for(std::size_t(0), rays.size(), [&](std::size_t i) {
        Hit hit;
        prims[i] = scene.intersect(rays[i], hit) ? hit.primId : kInvalidId;
      });
    });
    return prims;
  };
  const auto first = trace(1);
  BOOST_TEST(std::count(first.begin(), first.end(), kInvalidId) == 0);
  BOOST_TEST((trace(2) == first));
  BOOST_TEST((trace(1) == first));
}

BOOST_AUTO_TEST_CASE(case03_zero_and_negative_zero_directions) {
  for (AccelKind kind : kKinds) {
    Scene scene(optionsFor(kind));
    scene.createInstance(scene.createObject(makeBox({0, 0, 0}, {1, 1, 1})));
    scene.createInstance(scene.createObject(makeBox({1, 0, 0}, {2, 1, 1})));
    scene.commit();
    const ReferenceIntersector ref(scene);
    std::vector<Ray> rays;
    const float zeros[] = {0.0f, -0.0f};
    // Origins on the faces' planes (x = 0, 1, 2; y = 0, 1) and inside; axis directions.
    for (float x : {0.0f, 0.5f, 1.0f, 1.5f, 2.0f})
      for (float y : {0.0f, 0.25f, 1.0f})
        for (float z0 : zeros)
          for (float z1 : zeros) {
            rays.push_back({{x, y, -5.0f}, 0.0f, {z0, z1, 1.0f}, kInfinity});
            rays.push_back({{x, y, 5.0f}, 0.0f, {z1, z0, -1.0f}, kInfinity});
            rays.push_back({{x, -5.0f, 0.5f}, 0.0f, {z0, 1.0f, z1}, kInfinity});
            rays.push_back({{-5.0f, y, 0.5f}, 0.0f, {1.0f, z0, z1}, kInfinity});
          }
    std::size_t nanSeen = 0;
    for (const Ray& r : rays) {
      Hit hit;
      if (scene.intersect(r, hit) && (std::isnan(hit.t) || std::isnan(hit.u))) ++nanSeen;
    }
    BOOST_TEST(nanSeen == 0u);
    const DiffResult d = compareWithReference(scene, ref, rays);
    BOOST_TEST(d.mismatches == 0u, accelKindName(kind) << ": " << d.firstMismatch);
    BOOST_TEST(d.hits > 0u);
  }
}

BOOST_AUTO_TEST_CASE(case04_split_planes_through_primitives_and_flat_objects) {
  // A grid of axis-aligned unit quads in three orientations: every triangle lies in a likely
  // split plane. Plus a flat object (all z = 0) and rays lying in its plane.
  TriangleMesh grid;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int axis = 0; axis < 3; ++axis) {
        const auto base = static_cast<std::uint32_t>(grid.positions.size());
        for (int k = 0; k < 4; ++k) {
          Vec3f p;
          p[axis] = static_cast<float>(i);
          p[(axis + 1) % 3] = static_cast<float>(j) + ((k == 1 || k == 2) ? 1.0f : 0.0f);
          p[(axis + 2) % 3] = static_cast<float>((i + j) % 5) + (k >= 2 ? 1.0f : 0.0f);
          grid.positions.push_back(p);
        }
        grid.indices.insert(grid.indices.end(),
                            {base, base + 1, base + 2, base, base + 2, base + 3});
      }
  std::mt19937 rng(4);
  TriangleMesh flat = makeRandomTriangles(rng, 300, -5.0f, 5.0f, 1.0f);
  for (Vec3f& p : flat.positions) p.z = 0.0f;
  for (AccelKind kind : kKinds) {
    for (const TriangleMesh* mesh : {&grid, &flat}) {
      Scene scene(optionsFor(kind));
      scene.createInstance(scene.createObject(*mesh));
      scene.commit();
      std::vector<Ray> rays = makeRays(rng, scene.bounds(), 8000, mesh->positions);
      // Rays lying in z = 0 and in integer planes.
      for (int i = 0; i < 200; ++i)
        rays.push_back({{-10.0f, static_cast<float>(i % 7), static_cast<float>(i % 3)},
                        0.0f,
                        {1.0f, 0.01f * static_cast<float>(i % 5), 0.0f},
                        kInfinity});
      const ReferenceIntersector ref(scene);
      const DiffResult d = compareWithReference(scene, ref, rays);
      BOOST_TEST(d.mismatches == 0u, accelKindName(kind) << ": " << d.firstMismatch);
      BOOST_TEST(d.hits > 100u);
    }
  }
}

BOOST_AUTO_TEST_CASE(case05_degenerate_triangles_never_hit) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  m.indices = {0, 1, 2,   // collinear
               0, 0, 3,   // repeated vertex
               0, 4, 1,   // zero area (0 and 4 coincide)
               0, 1, 3};  // the only real triangle
  for (AccelKind kind : kKinds) {
    Scene scene(optionsFor(kind));
    const ObjectId obj = scene.createObject(m);
    scene.createInstance(obj);
    scene.commit();
    BOOST_TEST(scene.objectAccel(obj)->stats().degenerate == 3u);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.5f, 2.5f);
    std::size_t hits = 0;
    for (int i = 0; i < 5000; ++i) {
      Ray r{{u(rng), u(rng), 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, kInfinity};
      if (i % 2) r.direction = {u(rng), u(rng), -1.0f};
      Hit hit;
      if (scene.intersect(r, hit)) {
        ++hits;
        BOOST_TEST(hit.primId == 3u);
      }
    }
    BOOST_TEST(hits > 0u);
  }
}

BOOST_AUTO_TEST_CASE(case06_huge_and_tiny_scales) {
  const TriangleMesh base = makeIcosphere(2);
  double largestAgreeing = 0.0;
  for (double scale : {1e-4, 1e-2, 1.0, 1e2, 1e4}) {
    for (double translation : {1.0, 1e3, 1e5, 1e7}) {
      Scene scene;
      const Affine3d m = Affine3d::translation({translation, translation, translation}) *
                         Affine3d::scaling({scale, scale, scale});
      TriangleMesh mesh = base;
      for (Vec3f& p : mesh.positions) p = Vec3f(m.transformPoint(Vec3d(p)));
      scene.createInstance(scene.createObject(mesh));
      scene.commit();
      std::mt19937 rng(6);
      const std::vector<Ray> rays = makeRays(rng, scene.bounds(), 3000);
      const DiffResult d = compareWithReference(scene, ReferenceIntersector(scene), rays);
      BOOST_TEST_MESSAGE("scale " << scale << " translation " << translation << ": " << d.mismatches
                                  << " mismatches, " << d.ambiguous << " ambiguous of " << d.rays);
      if (d.mismatches == 0) largestAgreeing = std::max(largestAgreeing, translation);
      // Where float can still resolve the object (its size is at least ~1e-4 of its distance
      // from the origin) the answers must agree; beyond, results are reported only.
      if (scale / translation >= 1e-4) BOOST_TEST(d.mismatches == 0u, d.firstMismatch);
    }
  }
  BOOST_TEST_MESSAGE("largest translation with full agreement: " << largestAgreeing);
}

BOOST_AUTO_TEST_CASE(case06_normals_of_tiny_and_huge_triangles_stay_unit) {
  // cross(b - a, c - a) of these triangles lies far outside float's range (1e-44 and 1e40): the
  // normal must still come out unit length and perpendicular, flat and through an instance.
  for (double size : {1e-22, 1e20}) {
    TriangleMesh mesh;
    mesh.positions = {Vec3f(0, 0, 0), Vec3f(Vec3d(size, 0, 0)), Vec3f(Vec3d(0, size, size))};
    mesh.indices = {0, 1, 2};
    for (const Affine3d& m : {Affine3d::identity(), Affine3d::scaling({1.0, 1.0, -4.0})}) {
      Scene scene;
      scene.createInstance(scene.createObject(mesh), m);
      scene.commit();
      // Through the triangle's centroid, along -z from above (+z below for the mirrored one).
      const Vec3d centroid = m.transformPoint(Vec3d(size / 3, size / 3, size / 3));
      const Vec3d origin = centroid + Vec3d(0, 0, 2 * size);
      Hit hit;
      BOOST_TEST_REQUIRE(
          scene.intersect({Vec3f(origin), 0.0f, Vec3f(Vec3d(0, 0, -size)), kInfinity}, hit));
      // Expected: the inverse transpose of m applied to (0, -1, 1), up to sign.
      const Vec3d expected = normalize(Vec3d(0, -1, 1 / m.m[2][2]));
      const Vec3d n(hit.geometricNormal);
      BOOST_TEST(std::abs(length(n) - 1.0) < 1e-6);
      BOOST_TEST(std::abs(std::abs(dot(n, expected)) - 1.0) < 1e-6);
    }
  }
}

BOOST_AUTO_TEST_CASE(case07_instanced_t_within_16_ulps_up_to_1e6) {
  const TriangleMesh mesh = makeIcosphere(3);
  for (double translation : {1.0, 1e2, 1e4, 1e6}) {
    Scene scene;
    const Affine3d m = Affine3d::translation({translation, -translation, translation}) *
                       Affine3d::rotation({1, 2, 3}, 30.0);
    scene.createInstance(scene.createObject(mesh), m);
    scene.commit();
    const ReferenceIntersector ref(scene);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    double worstUlps = 0.0;
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
      Ray r;
      const Vec3f centre{static_cast<float>(translation), static_cast<float>(-translation),
                         static_cast<float>(translation)};
      r.origin = centre + Vec3f{u(rng), u(rng), u(rng)} * 4.0f;
      r.direction = centre + Vec3f{u(rng), u(rng), u(rng)} * 0.5f - r.origin;
      const ReferenceHit expected = ref.intersect(r);
      Hit hit;
      // Only the reference's own ambiguity relative to the world origin would skip every ray at
      // 1e6; here the question is t on the same triangle, so compare wherever both agree on it.
      if (!expected.hit || !scene.intersect(r, hit) || hit.primId != expected.primId) continue;
      ++compared;
      const double ulp = std::nextafter(static_cast<float>(expected.t), kInfinity) -
                         static_cast<float>(expected.t);
      worstUlps = std::max(worstUlps, std::abs(double(hit.t) - expected.t) / ulp);
    }
    BOOST_TEST_MESSAGE("translation " << translation << ": worst t error " << worstUlps
                                      << " ulps through the instance over " << compared << " rays");
    BOOST_TEST(compared > 1000);
    BOOST_TEST(worstUlps <= 16.0);
  }
}

BOOST_AUTO_TEST_CASE(case08_scaled_instances_share_t) {
  // The same box, once in world space and once as a non-uniformly scaled instance placed in
  // front of it: the instance must win, with t comparable to the world-space object's.
  Scene scene;
  scene.createInstance(scene.createObject(makeBox({-1, -1, 4}, {1, 1, 5})));
  const ObjectId unit = scene.createObject(makeBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}));
  const InstanceId scaled = scene.createInstance(
      unit, Affine3d::translation({0, 0, 2}) * Affine3d::scaling({4.0, 3.0, 0.5}));
  scene.commit();
  Ray r{{0.1f, 0.2f, 0.0f}, 0.0f, {0.0f, 0.0f, 2.0f}, kInfinity};  // non-unit direction
  Hit hit;
  BOOST_TEST(scene.intersect(r, hit));
  BOOST_TEST(hit.instanceId == scaled);
  BOOST_TEST(std::abs(hit.t - 0.875f) <= 2e-7f);  // front face z = 1.75, |direction| 2
  std::mt19937 rng(9);
  const DiffResult d =
      compareWithReference(scene, ReferenceIntersector(scene), makeRays(rng, scene.bounds(), 5000));
  BOOST_TEST(d.mismatches == 0u, d.firstMismatch);
}

BOOST_AUTO_TEST_CASE(case09_mirrored_instances_keep_outward_normals) {
  const TriangleMesh box = makeBox({-1, -1, -1}, {1, 1, 1});
  for (const Affine3d& m :
       {Affine3d::scaling({-1.0, 1.0, 1.0}),
        Affine3d::scaling({-2.0, 0.5, 3.0}) * Affine3d::rotation({0, 1, 0}, 20)}) {
    BOOST_TEST(m.determinant() < 0.0);
    Scene instanced;
    instanced.createInstance(instanced.createObject(box), m);
    instanced.commit();
    TriangleMesh flattened = box;
    for (Vec3f& p : flattened.positions) p = Vec3f(m.transformPoint(Vec3d(p)));
    Scene flat;
    flat.createInstance(flat.createObject(flattened));
    flat.commit();
    std::mt19937 rng(10);
    for (const Ray& r : makeRays(rng, instanced.bounds(), 2000)) {
      Hit a, b;
      const bool hitA = instanced.intersect(r, a), hitB = flat.intersect(r, b);
      BOOST_TEST(hitA == hitB);
      if (!hitA || !hitB) continue;
      // Outward: a ray from outside the box meets a normal pointing against it.
      if (!instanced.bounds().contains(r.origin))
        BOOST_TEST(dot(a.geometricNormal, r.direction) < 0.0f);
      // Shading sees |N.D| only for two-sided use: identical to the flattened mesh.
      BOOST_TEST(std::abs(std::abs(dot(a.geometricNormal, b.geometricNormal)) - 1.0f) < 1e-5f);
    }
  }
}

BOOST_AUTO_TEST_CASE(case10_singular_matrices_rejected_tiny_scales_render) {
  Scene scene;
  const ObjectId box = scene.createObject(makeBox());
  BOOST_CHECK_EXCEPTION(
      scene.createInstance(box, Affine3d::scaling({1.0, 0.0, 1.0})), Error, [](const Error& e) {
        return std::string(e.what()).find("createInstance") != std::string::npos &&
               std::string(e.what()).find("singular") != std::string::npos;
      });
  BOOST_TEST(scene.instanceCount() == 0u);
  const InstanceId tiny = scene.createInstance(box, Affine3d::scaling({1.0, 1e-6, 1.0}));
  scene.commit();
  Hit hit;
  BOOST_TEST(scene.intersect({{0.5f, 0.5e-6f, -1.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity}, hit));
  BOOST_TEST(hit.instanceId == tiny);
  BOOST_TEST(std::isfinite(hit.t));
  BOOST_CHECK_THROW(scene.setInstanceTransform(tiny, Affine3d::scaling({0.0, 0.0, 0.0})), Error);
  BOOST_TEST(scene.instanceTransform(tiny).m[1][1] == 1e-6);  // unchanged
}

BOOST_AUTO_TEST_CASE(case11_interval_ends_are_inclusive) {
  for (AccelKind kind : kKinds) {
    Scene scene(optionsFor(kind));
    scene.createInstance(scene.createObject(intervalTriangle()));
    scene.commit();
    checkInclusiveIntervalEnds(scene);
  }
}

BOOST_AUTO_TEST_CASE(case12_infinite_and_huge_tfar) {
  for (AccelKind kind : kKinds) {
    Scene scene(optionsFor(kind));
    scene.createInstance(scene.createObject(makeBox({-1e8f, -1e8f, 1e9f}, {1e8f, 1e8f, 2e9f})));
    scene.createInstance(scene.createObject(makeBox({5, 5, 5}, {6, 6, 6})));
    scene.commit();
    for (float tfar : {kInfinity, 3.0e38f, std::numeric_limits<float>::max()}) {
      Hit hit;
      BOOST_TEST(scene.intersect({{0, 0, 0}, 0.0f, {0, 0, 1}, tfar}, hit));
      BOOST_TEST(hit.t == 1e9f);
      BOOST_TEST(scene.occluded({{0, 0, 0}, 0.0f, {0, 0, 1}, tfar}));
    }
    Hit hit;
    BOOST_TEST(scene.intersect({{0, 0, 0}, 0.0f, {0, 0, 1e-3f}, kInfinity}, hit));
    BOOST_TEST(std::isfinite(hit.t));
  }
}

BOOST_AUTO_TEST_CASE(case18_coincident_and_touching_instances) {
  Scene coincident;
  const ObjectId sphere = coincident.createObject(makeIcosphere(1));
  for (int i = 0; i < 1000; ++i)
    coincident.createInstance(sphere, Affine3d::translation({3, 3, 3}));
  coincident.commit();
  BOOST_TEST(coincident.topLevel().stats().maxDepth <= 64u);
  std::mt19937 rng(11);
  DiffResult d = compareWithReference(coincident, ReferenceIntersector(coincident),
                                      makeRays(rng, coincident.bounds(), 300));
  BOOST_TEST(d.mismatches == 0u, d.firstMismatch);
  BOOST_TEST(d.hits > 0u);

  Scene touching;  // a 10x10x3 grid of unit boxes sharing faces
  const ObjectId box = touching.createObject(makeBox());
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y)
      for (int z = 0; z < 3; ++z)
        touching.createInstance(box, Affine3d::translation({double(x), double(y), double(z)}));
  touching.commit();
  BOOST_TEST(touching.topLevel().stats().maxDepth <= 64u);
  BOOST_TEST(touching.topLevel().stats().leaves > 1u);
  d = compareWithReference(touching, ReferenceIntersector(touching),
                           makeRays(rng, touching.bounds(), 3000));
  BOOST_TEST(d.mismatches == 0u, d.firstMismatch);
}
