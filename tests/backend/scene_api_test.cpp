// The C++ API rejects bad input with a message naming the call and leaves the scene as it was.
#define BOOST_TEST_MODULE scene_api
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "TestGeometry.h"
#include "tracegraph/backend/Error.h"

using namespace tg;
using namespace tg::test;

namespace {

/// Fingerprint of a committed scene: counts plus the hits of a fixed ray set.
struct Snapshot {
  std::size_t objects, instances;
  std::vector<std::tuple<float, std::uint32_t, std::uint32_t>> hits;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const Scene& scene) {
  Snapshot s{scene.objectCount(), scene.instanceCount(), {}};
  std::mt19937 rng(3);
  for (const Ray& r : makeRays(rng, Box3f({-2, -2, -2}, {4, 4, 4}), 500)) {
    Hit hit;
    scene.intersect(r, hit);
    s.hits.emplace_back(hit.t, hit.instanceId, hit.primId);
  }
  return s;
}

/// Runs `call`, expects tg::Error whose message contains `name`, then checks the scene.
template <class F>
void expectRejected(Scene& scene, const std::string& name, F&& call) {
  const Snapshot before = snapshot(scene);
  bool thrown = false;
  try {
    call();
  } catch (const Error& e) {
    thrown = true;
    BOOST_TEST(std::string(e.what()).find(name) != std::string::npos,
               "message '" << e.what() << "' should name " << name);
  }
  BOOST_TEST(thrown, name << " accepted bad input");
  scene.commit();
  BOOST_TEST((snapshot(scene) == before), name << " changed the scene");
}

}  // namespace

BOOST_AUTO_TEST_CASE(bad_meshes_are_rejected) {
  Scene scene;
  const ObjectId box = scene.createObject(makeBox());
  scene.createInstance(box, Affine3d::translation({1, 0, 0}));
  scene.commit();
  TriangleMesh outOfRange = makeBox();
  outOfRange.indices[5] = 8;
  TriangleMesh notTriples = makeBox();
  notTriples.indices.pop_back();
  TriangleMesh nan = makeBox();
  nan.positions[2].y = std::nanf("");
  TriangleMesh inf = makeBox();
  inf.positions[1].x = kInfinity;
  TriangleMesh badNormals = makeBox();
  badNormals.normals.resize(3);
  for (const TriangleMesh* m : {&outOfRange, &notTriples, &nan, &inf, &badNormals}) {
    expectRejected(scene, "Scene::createObject", [&] { scene.createObject(*m); });
    expectRejected(scene, "Scene::setObjectMesh", [&] { scene.setObjectMesh(box, *m); });
  }
  std::vector<Vec3f> points = makeBox().positions;
  points[0].z = std::nanf("");
  expectRejected(scene, "Scene::setObjectPositions",
                 [&] { scene.setObjectPositions(box, points); });
  points.pop_back();
  expectRejected(scene, "Scene::setObjectPositions",
                 [&] { scene.setObjectPositions(box, points); });
}

BOOST_AUTO_TEST_CASE(unknown_ids_and_bad_matrices_are_rejected) {
  Scene scene;
  const ObjectId box = scene.createObject(makeBox());
  const InstanceId inst = scene.createInstance(box);
  scene.commit();
  expectRejected(scene, "Scene::createInstance", [&] { scene.createInstance(42); });
  expectRejected(scene, "Scene::setInstanceTransform",
                 [&] { scene.setInstanceTransform(7, Affine3d{}); });
  expectRejected(scene, "Scene::destroyInstance", [&] { scene.destroyInstance(9); });
  expectRejected(scene, "Scene::destroyObject", [&] { scene.destroyObject(box); });  // in use
  Affine3d nan;
  nan.m[1][3] = std::nan("");
  expectRejected(scene, "Scene::setInstanceTransform",
                 [&] { scene.setInstanceTransform(inst, nan); });
  expectRejected(scene, "Scene::setInstanceTransform", [&] {
    scene.setInstanceTransform(inst, Affine3d::scaling({1.0, 1.0, 0.0}));
  });
  Affine3d rankDeficient;  // third column = first + second
  rankDeficient.m[0][2] = 1.0;
  rankDeficient.m[1][2] = 1.0;
  rankDeficient.m[2][2] = 0.0;
  expectRejected(scene, "Scene::createInstance", [&] { scene.createInstance(box, rankDeficient); });
}

BOOST_AUTO_TEST_CASE(queries_see_only_committed_state) {
  Scene scene;
  // Vertex normals along z, so that surfaceAt's shading normal shows which matrix mapped it.
  TriangleMesh mesh = makeBox();
  mesh.normals.assign(mesh.positions.size(), Vec3f(0.0f, 0.0f, -1.0f));
  const ObjectId box = scene.createObject(mesh);
  // A destroyed instance before it, so that instance ids and record order differ.
  scene.destroyInstance(scene.createInstance(box, Affine3d::translation({0, 5, 0})));
  const InstanceId inst = scene.createInstance(box);
  scene.commit();
  const Ray r{{0.5f, 0.5f, -1.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity};
  Hit hit;
  BOOST_TEST(scene.intersect(r, hit));
  const Vec3f committedNormal = hit.geometricNormal;
  BOOST_TEST(std::abs(committedNormal.z) == 1.0f);
  // A pending rotation changes neither the hit nor its normal, by single ray or by packet.
  scene.setInstanceTransform(inst, Affine3d::rotation(Vec3d(1, 0, 0), 90.0));
  BOOST_TEST(scene.hasPendingChanges());
  BOOST_TEST(scene.intersect(r, hit));
  BOOST_TEST(hit.geometricNormal.x == committedNormal.x);
  BOOST_TEST(hit.geometricNormal.y == committedNormal.y);
  BOOST_TEST(hit.geometricNormal.z == committedNormal.z);
  const std::vector<Ray> packet(8, r);
  std::vector<Hit> packetHits(8);
  TraversalContext ctx;
  scene.intersect(packet, packetHits, ctx);
  for (const Hit& h : packetHits) {
    BOOST_TEST(h.valid());
    BOOST_TEST(h.geometricNormal.z == committedNormal.z);
  }
  BOOST_TEST(scene.surfaceAt(r, hit).shadingNormal.z == committedNormal.z);
  scene.setInstanceTransform(inst, Affine3d::translation({10, 0, 0}));
  BOOST_TEST(scene.intersect(r, hit));  // still the committed state
  scene.commit();
  BOOST_TEST(!scene.intersect(r, hit));
  scene.destroyInstance(inst);
  scene.commit();
  scene.destroyObject(box);
  BOOST_TEST(scene.objectCount() == 0u);
  BOOST_TEST(scene.instanceCount() == 0u);
}

BOOST_AUTO_TEST_CASE(untraceable_rays_never_hit) {
  Scene scene;
  scene.createInstance(scene.createObject(makeBox()));
  scene.commit();
  Hit hit;
  BOOST_TEST(!scene.intersect({{0.5f, 0.5f, -1.0f}, 0.0f, {0.0f, 0.0f, 0.0f}, kInfinity}, hit));
  BOOST_TEST(!scene.intersect({{std::nanf(""), 0.5f, -1.0f}, 0.0f, {0, 0, 1}, kInfinity}, hit));
  BOOST_TEST(!scene.intersect({{0.5f, 0.5f, -1.0f}, 0.0f, {0, kInfinity, 1}, kInfinity}, hit));
  BOOST_TEST(!scene.occluded({{0.5f, 0.5f, -1.0f}, 2.0f, {0, 0, 1}, 1.0f}));
}

BOOST_AUTO_TEST_CASE(is_traceable_follows_its_definition_for_every_special_value) {
  // isTraceable tests the ray's two halves in vectors; its documented rule, written out here
  // component by component, must give the same answer for every mix of special values.
  const float values[] = {0.0f,
                          -0.0f,
                          1.0f,
                          -2.5f,
                          kInfinity,
                          -kInfinity,
                          std::nanf(""),
                          std::numeric_limits<float>::max(),
                          -std::numeric_limits<float>::max(),
                          std::numeric_limits<float>::denorm_min()};
  const auto finite = [](float x) { return std::isfinite(x); };
  std::size_t traceable = 0, checked = 0;
  for (const float a : values)
    for (const float b : values)
      for (const float c : values)
        for (const float t : values) {
          // Origin, direction and the interval each take their turn with the special values.
          const Ray rays[] = {{{a, b, c}, 0.0f, {0.0f, 1.0f, 0.0f}, t},
                              {{1.0f, 2.0f, 3.0f}, t, {a, b, c}, 1.0f},
                              {{a, 0.0f, 0.0f}, t, {b, c, 1.0f}, a}};
          for (const Ray& r : rays) {
            const bool expected =
                finite(r.origin.x) && finite(r.origin.y) && finite(r.origin.z) &&
                finite(r.direction.x) && finite(r.direction.y) && finite(r.direction.z) &&
                !(r.direction.x == 0.0f && r.direction.y == 0.0f && r.direction.z == 0.0f) &&
                !std::isnan(r.tnear) && !std::isnan(r.tfar) && r.tnear <= r.tfar;
            BOOST_TEST(isTraceable(r) == expected);
            traceable += expected ? 1 : 0;
            ++checked;
          }
        }
  // Both answers occur often, so neither a constant nor a swapped test can pass.
  BOOST_TEST(traceable > checked / 10);
  BOOST_TEST(traceable < checked / 2);
}

BOOST_AUTO_TEST_CASE(occluder_hints_rest_while_they_keep_failing_and_return_when_they_pay) {
  // Two unit boxes; the hint names a triangle of the first. Rays beside both boxes walk and
  // miss: a failing hint test is the only triangle test they make.
  Scene scene;
  const ObjectId box = scene.createObject(makeBox());
  scene.createInstance(box);
  scene.createInstance(box, Affine3d::translation({4, 0, 0}));
  scene.commit();
  const auto through = [](float x) { return Ray{{x, 0.2f, -1.0f}, 0.0f, {0, 0, 1}, 3.0f}; };
  TraversalContext ctx;
  BOOST_TEST(scene.occluded(through(0.6f), ctx));

  // 200 rays past both boxes: the hint fails every time, so after a while it is tested on one
  // query in a few only.
  const std::uint64_t testsBefore = ctx.triangleTests;
  for (int i = 0; i < 200; ++i) BOOST_TEST(!scene.occluded(through(2.5f), ctx));
  const std::uint64_t hintTests = ctx.triangleTests - testsBefore;
  BOOST_TEST(hintTests >= 20u);
  BOOST_TEST(hintTests < 60u);

  // Rays the hint's triangle blocks again: the tests it still makes succeed, and once its rate
  // has recovered every query is answered by it, without a walk.
  for (int i = 0; i < 200; ++i) BOOST_TEST(scene.occluded(through(0.6f), ctx));
  const std::uint64_t visitsBefore = ctx.nodeVisits;
  for (int i = 0; i < 20; ++i) BOOST_TEST(scene.occluded(through(0.6f), ctx));
  BOOST_TEST(ctx.nodeVisits == visitsBefore);
}

BOOST_AUTO_TEST_CASE(occluder_hints_answer_repeats_and_never_cross_scenes_or_commits) {
  // Five unit boxes along x; shadow-like rays along +z through one of them.
  Scene a;
  const ObjectId box = a.createObject(makeBox());
  std::vector<InstanceId> row;
  for (int i = 0; i < 5; ++i)
    row.push_back(a.createInstance(box, Affine3d::translation({2.0 * i, 0, 0})));
  a.commit();
  const auto through = [](float x) { return Ray{{x, 0.2f, -1.0f}, 0.0f, {0, 0, 1}, 3.0f}; };

  TraversalContext ctx;
  BOOST_TEST(a.occluded(through(8.6f), ctx));
  // The same blocker again (both rays cross the box's bottom face on the same side of either
  // diagonal, so through the same triangle): answered by the hint's triangle, without a node visit.
  const std::uint64_t visits = ctx.nodeVisits;
  BOOST_TEST(a.occluded(through(8.7f), ctx));
  BOOST_TEST(ctx.nodeVisits == visits);
  // Rays the hint's triangle does not block still get the walk's answer.
  BOOST_TEST(a.occluded(through(0.5f), ctx));
  BOOST_TEST(!a.occluded(through(1.5f), ctx));

  // A hint names an instance record of one build: another scene with one instance, and the
  // same scene after a commit that moved the blocker, must not take it.
  BOOST_TEST(a.occluded(through(8.5f), ctx));
  Scene b;
  b.createInstance(b.createObject(makeBox()));
  b.commit();
  BOOST_TEST(!b.occluded(through(8.5f), ctx));
  BOOST_TEST(b.occluded(through(0.5f), ctx));
  BOOST_TEST(a.occluded(through(8.5f), ctx));
  a.setInstanceTransform(row[4], Affine3d::translation({20, 0, 0}));
  a.commit();
  BOOST_TEST(!a.occluded(through(8.5f), ctx));

  // Packets with a context carried from ray to ray answer as fresh single rays do.
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) rays.push_back(through(-0.5f + 0.17f * static_cast<float>(i)));
  std::vector<std::uint8_t> packets(rays.size());
  for (int pass = 0; pass < 2; ++pass) {
    a.occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(packets), ctx);
    for (std::size_t i = 0; i < rays.size(); ++i)
      BOOST_TEST(static_cast<bool>(packets[i]) == a.occluded(rays[i]), "ray " << i);
  }
}

BOOST_AUTO_TEST_CASE(uv_area_per_world_area_follows_the_mesh_and_the_instance) {
  // A 2 x 2 square mapped onto the unit uv square: 1/4 of uv area per unit of area, 1/36 under
  // a uniform scale by 3, 1/16 under a scale of (2, 4, 1) (area scale 8, taken as 8^(2/3) = 4),
  // and nothing for a mesh without uvs.
  Scene scene;
  TriangleMesh square;
  square.positions = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  square.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  square.indices = {0, 1, 2, 0, 2, 3};
  TriangleMesh bare = square;
  bare.uvs.clear();
  const ObjectId textured = scene.createObject(square), plain = scene.createObject(bare);
  const Affine3d at = Affine3d::translation({0, 0, -10});
  const InstanceId unit = scene.createInstance(textured, at);
  const InstanceId scaled = scene.createInstance(
      textured, Affine3d::translation({10, 0, -10}) * Affine3d::scaling({3, 3, 3}));
  const InstanceId stretched = scene.createInstance(
      textured, Affine3d::translation({20, 0, -10}) * Affine3d::scaling({2, 4, 1}));
  const InstanceId untextured = scene.createInstance(plain, Affine3d::translation({30, 0, -10}));
  scene.commit();
  const auto ratioAt = [&](float x, float y, InstanceId expected) {
    Hit hit;
    Ray ray;
    ray.origin = {x, y, 0};
    ray.direction = {0, 0, -1};
    BOOST_TEST_REQUIRE(scene.intersect(ray, hit));
    BOOST_TEST_REQUIRE(hit.instanceId == expected);
    return scene.uvAreaPerWorldArea(hit);
  };
  BOOST_TEST(ratioAt(1.5f, 0.5f, unit) == 0.25f);
  BOOST_TEST(ratioAt(0.5f, 1.5f, unit) == 0.25f);  // the other triangle
  BOOST_TEST(std::abs(ratioAt(11.0f, 1.0f, scaled) - 1.0f / 36.0f) < 1e-7f);
  BOOST_TEST(std::abs(ratioAt(21.0f, 1.0f, stretched) - 1.0f / 16.0f) < 1e-7f);
  BOOST_TEST(ratioAt(31.0f, 1.0f, untextured) == 0.0f);
  BOOST_TEST(scene.uvAreaPerWorldArea(Hit{}) == 0.0f);
}
