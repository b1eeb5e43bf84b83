// The BVH engine: object BVHs (bvh, bvh-fast with refit) and the top-level BVH, judged by the
// double-precision reference and by the kd-trees, on the hard cases that concern traversal.
#define BOOST_TEST_MODULE bvh
#include <boost/test/unit_test.hpp>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "IntervalChecks.h"
#include "IsaGuard.h"
#include "TestGeometry.h"
#include "tracegraph/backend/Simd.h"

using namespace tg;
using namespace tg::test;

namespace {

constexpr AccelKind kBvhKinds[] = {AccelKind::Bvh, AccelKind::BvhFast};
constexpr TopLevelKind kTopLevels[] = {TopLevelKind::KdTree, TopLevelKind::Bvh};

SceneOptions optionsFor(AccelKind kind, TopLevelKind topLevel = TopLevelKind::Bvh) {
  SceneOptions o;
  o.staticAccel = kind;
  o.deformingAccel = kind;
  o.topLevel = topLevel;
  return o;
}

std::string nameOf(AccelKind kind, TopLevelKind topLevel) {
  return std::string(accelKindName(kind)) + "/" + std::string(topLevelKindName(topLevel));
}

/// Closest hit and occlusion of one accelerator for a world-space ray (no instance).
struct ObjectAnswer {
  bool hit = false;
  Hit record;
  bool occluded = false;
};

ObjectAnswer query(const ObjectAccel& accel, const Ray& r) {
  ObjectAnswer a;
  TraversalContext ctx;
  ObjectRay ray(r.origin, r.direction, r.tnear, r.tfar, 0, 0);
  a.hit = accel.intersect(ray, a.record, ctx);
  ctx = TraversalContext{};
  a.occluded = accel.occluded(ObjectRay(r.origin, r.direction, r.tnear, r.tfar, 0, 0), ctx);
  return a;
}

/// The double-precision reference for one mesh in world space.
class MeshReference {
 public:
  explicit MeshReference(const TriangleMesh& mesh) {
    scene_.createInstance(scene_.createObject(mesh));
    scene_.commit();
    reference_ = std::make_unique<ReferenceIntersector>(scene_);
  }
  /// True when float rounding may decide this ray's answer: it grazes an edge or vertex, ends
  /// at a surface, or meets two triangles at nearly the same t. There the watertight test may
  /// accept a triangle at a t outside its own box, so which of the candidates an accelerator
  /// reports depends on the order it meets them in.
  bool ambiguous(const Ray& r) const {
    const ReferenceHit h = reference_->intersect(r);
    bool occlusionAmbiguous = false;
    reference_->occluded(r, &occlusionAmbiguous);
    return h.hitAmbiguous || h.primAmbiguous || occlusionAmbiguous;
  }

 private:
  Scene scene_;
  std::unique_ptr<ReferenceIntersector> reference_;
};

/// Number of rays on which two accelerators answer differently (t, triangle, barycentrics,
/// occlusion). With a reference, rays it calls ambiguous are not counted; everywhere else the
/// same watertight test and tie rule must give bit-identical answers whatever the tree.
std::size_t countDifferences(const ObjectAccel& a, const ObjectAccel& b,
                             const std::vector<Ray>& rays, std::string& first,
                             const MeshReference* reference = nullptr) {
  std::size_t differences = 0;
  for (const Ray& r : rays) {
    const ObjectAnswer x = query(a, r), y = query(b, r);
    const bool same = x.hit == y.hit && x.occluded == y.occluded && x.record.t == y.record.t &&
                      x.record.primId == y.record.primId && x.record.u == y.record.u &&
                      x.record.v == y.record.v;
    // The reference is slow: consult it only where the answers differ.
    if (same || (reference && reference->ambiguous(r))) continue;
    if (differences++ == 0) first = describe(r);
  }
  return differences;
}

std::unique_ptr<ObjectAccel> built(AccelKind kind, const TriangleMesh& mesh) {
  std::unique_ptr<ObjectAccel> accel = createObjectAccel(kind);
  accel->build(mesh);
  return accel;
}

/// True when every non-degenerate triangle of `mesh` lies in `box`.
bool containsTriangles(const Box3f& box, const TriangleMesh& mesh) {
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3f a = mesh.positions[mesh.indices[i]], b = mesh.positions[mesh.indices[i + 1]],
                c = mesh.positions[mesh.indices[i + 2]];
    if (isDegenerateTriangle(a, b, c)) continue;
    if (!box.contains(a) || !box.contains(b) || !box.contains(c)) return false;
  }
  return true;
}

void checkScene(const Scene& scene, const std::vector<Ray>& rays, const std::string& label,
                std::size_t minHits = 1) {
  const DiffResult d = compareWithReference(scene, ReferenceIntersector(scene), rays);
  BOOST_TEST_MESSAGE(label << ": " << d.rays << " rays, " << d.hits << " hits, " << d.ambiguous
                           << " ambiguous, " << d.mismatches << " mismatches");
  BOOST_TEST(d.mismatches == 0u, label << ": " << d.firstMismatch);
  BOOST_TEST(d.hits >= minHits, label << ": too few hits");
}

/// Rays of `rays` whose packet answers (Scene::intersect and Scene::occluded over spans, one
/// context carried through) differ from fresh single rays' in t, triangle, instance or
/// occlusion; `hits` receives the single rays' hit count.
std::size_t packetMismatches(const Scene& scene, const std::vector<Ray>& rays,
                             std::size_t* hits = nullptr) {
  std::vector<Hit> packetHits(rays.size());
  std::vector<std::uint8_t> packetOccluded(rays.size());
  TraversalContext ctx;
  scene.intersect(rays, packetHits, ctx);
  scene.occluded(rays, packetOccluded, ctx);
  std::size_t mismatches = 0, found = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Hit hit;
    found += scene.intersect(rays[i], hit) ? 1 : 0;
    if (hit.t != packetHits[i].t || hit.primId != packetHits[i].primId ||
        hit.instanceId != packetHits[i].instanceId ||
        scene.occluded(rays[i]) != (packetOccluded[i] != 0))
      ++mismatches;
  }
  if (hits) *hits = found;
  return mismatches;
}

/// A mesh moved the way deformers move meshes: a smooth wave plus a twist.
TriangleMesh deformed(const TriangleMesh& mesh, float amount) {
  TriangleMesh out = mesh;
  for (Vec3f& p : out.positions) {
    const float angle = amount * p.z;
    const float c = std::cos(angle), s = std::sin(angle);
    p = Vec3f{c * p.x - s * p.y, s * p.x + c * p.y, p.z + amount * 0.3f * std::sin(3.0f * p.x)};
  }
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(kinds_are_named_and_created) {
  BOOST_TEST(accelKindName(AccelKind::Bvh) == "bvh");
  BOOST_TEST(accelKindName(AccelKind::BvhFast) == "bvh-fast");
  BOOST_TEST(topLevelKindName(TopLevelKind::Bvh) == "bvh");
  for (AccelKind kind : kBvhKinds) BOOST_TEST((createObjectAccel(kind)->kind() == kind));
  BOOST_TEST((createTopLevelAccel(TopLevelKind::Bvh)->kind() == TopLevelKind::Bvh));
  // The BVH engine is the default; the paper's kd-trees stay one option away.
  const SceneOptions defaults;
  BOOST_TEST((defaults.staticAccel == AccelKind::Bvh));
  BOOST_TEST((defaults.deformingAccel == AccelKind::BvhFast));
  BOOST_TEST((defaults.topLevel == TopLevelKind::Bvh));
  const SceneOptions kd = sceneOptionsFor(Engine::KdTree);
  BOOST_TEST((kd.staticAccel == AccelKind::SahKdTree));
  BOOST_TEST((kd.deformingAccel == AccelKind::FastKdTree));
  BOOST_TEST((kd.topLevel == TopLevelKind::KdTree));
  Engine engine = Engine::KdTree;
  BOOST_TEST((parseEngine("bvh", engine) && engine == Engine::Bvh));
  BOOST_TEST(!parseEngine("octree", engine));
  Scene scene(optionsFor(AccelKind::Bvh));
  BOOST_TEST((scene.topLevel().kind() == TopLevelKind::Bvh));
}

BOOST_AUTO_TEST_CASE(random_meshes_match_reference) {
  std::mt19937 rng(21);
  for (const std::size_t n : {1u, 2u, 5u, 60u, 3000u}) {
    const TriangleMesh mesh = makeRandomTriangles(rng, n, -4.0f, 4.0f, 1.5f);
    for (AccelKind kind : kBvhKinds) {
      Scene scene(optionsFor(kind));
      const ObjectId id = scene.createObject(mesh);
      scene.createInstance(id);
      scene.commit();
      const BuildStats& st = scene.objectAccel(id)->stats();
      BOOST_TEST(st.triangles == n);
      BOOST_TEST(st.primReferences == n);  // random triangles are never degenerate
      BOOST_TEST(st.maxDepth <= 64u);
      BOOST_TEST(st.sahCost > 0.0);
      BOOST_TEST(!st.refitted);
      std::mt19937 rayRng(static_cast<unsigned>(n));
      checkScene(scene, makeRays(rayRng, scene.bounds(), 3000, mesh.positions),
                 std::string(accelKindName(kind)) + " " + std::to_string(n) + " triangles");
    }
  }
}

BOOST_AUTO_TEST_CASE(hits_are_identical_to_the_kd_trees) {
  // Same watertight test, same tie rule: every accelerator returns the very same hit.
  std::mt19937 rng(22);
  TriangleMesh mesh = makeIcosphere(3);
  const TriangleMesh soup = makeRandomTriangles(rng, 2000, -1.5f, 1.5f, 0.4f);
  for (const Vec3f& p : soup.positions) {
    mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
    mesh.positions.push_back(p);
  }
  const std::vector<Ray> rays = makeRays(rng, mesh.bounds(), 20000, mesh.positions);
  const auto sahKd = built(AccelKind::SahKdTree, mesh);
  const MeshReference meshReference(mesh);
  for (AccelKind kind : {AccelKind::FastKdTree, AccelKind::Bvh, AccelKind::BvhFast}) {
    std::string first;
    const std::size_t d = countDifferences(*built(kind, mesh), *sahKd, rays, first, &meshReference);
    BOOST_TEST(d == 0u, accelKindName(kind) << " differs from sah-kd, first for " << first);
  }
}

BOOST_AUTO_TEST_CASE(instanced_scenes_match_reference) {
  for (AccelKind kind : {AccelKind::SahKdTree, AccelKind::Bvh, AccelKind::BvhFast}) {
    std::mt19937 rng(23);
    Scene scene(optionsFor(kind, TopLevelKind::Bvh));
    std::vector<Vec3f> targets;
    for (int o = 0; o < 5; ++o) {
      const TriangleMesh mesh =
          o == 0 ? makeIcosphere(1) : makeRandomTriangles(rng, 30, -1.0f, 1.0f, 0.6f);
      const ObjectId id = scene.createObject(mesh);
      for (int i = 0; i < 24; ++i) {
        const Affine3d m = randomTransform(rng, 10.0, true);
        scene.createInstance(id, m);
        for (const Vec3f& p : mesh.positions) targets.push_back(Vec3f(m.transformPoint(Vec3d(p))));
      }
    }
    scene.commit();
    BOOST_TEST(scene.topLevel().stats().references == 120u);
    checkScene(scene, makeRays(rng, scene.bounds(), 1500, targets),
               "instanced " + std::string(accelKindName(kind)) + "/bvh", 300);
  }
}

BOOST_AUTO_TEST_CASE(many_instances_match_reference) {
  // Enough instances for the parallel top-level build path.
  std::mt19937 rng(24);
  TriangleMesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  Scene scene(optionsFor(AccelKind::Bvh));
  const ObjectId id = scene.createObject(quad);
  for (int i = 0; i < 12000; ++i) scene.createInstance(id, randomTransform(rng, 60.0, true));
  scene.commit();
  const TopLevelStats& st = scene.topLevel().stats();
  BOOST_TEST(st.references == 12000u);
  BOOST_TEST(st.maxDepth <= 64u);
  BOOST_TEST(st.leaves >= 12000u / 2);
  checkScene(scene, makeRays(rng, scene.bounds(), 400), "12000 instances", 40);
}

BOOST_AUTO_TEST_CASE(identity_instances_are_entered_by_subtree_with_unchanged_answers) {
  // Static geometry is identity instances of BVH objects (overlapping chunks, as the scene
  // graph makes them): the top level holds their subtrees, up to two entries per instance, and
  // answers stay the reference's, for single rays and for packets.
  std::mt19937 rng(31);
  Scene scene(optionsFor(AccelKind::Bvh, TopLevelKind::Bvh));
  std::vector<Vec3f> targets;
  for (int o = 0; o < 3; ++o) {
    const TriangleMesh mesh = makeRandomTriangles(rng, 400, -4.0f + 1.5f * float(o), 4.0f, 0.5f);
    scene.createInstance(scene.createObject(mesh));
    targets.insert(targets.end(), mesh.positions.begin(), mesh.positions.end());
  }
  scene.createInstance(scene.createObject(makeIcosphere(2)), randomTransform(rng, 3.0, true));
  scene.commit();
  const TopLevelStats& st = scene.topLevel().stats();
  BOOST_TEST(st.instances == 4u);
  BOOST_TEST(st.references > 4u);
  BOOST_TEST(st.references <= 8u);
  checkScene(scene, makeRays(rng, scene.bounds(), 3000, targets), "subtree entries", 300);

  // A pinhole grid, so that neighbouring rays share direction signs and walk as packets.
  std::vector<Ray> rays;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const Vec3f origin{0.1f, 0.2f, 12.0f};
      const Vec3f target{-5.0f + 10.0f * float(x) / 63.0f, -5.0f + 10.0f * float(y) / 63.0f, -5.0f};
      rays.push_back(Ray{origin, 0.0f, target - origin, kInfinity});
    }
  std::size_t hits = 0;
  BOOST_TEST(packetMismatches(scene, rays, &hits) == 0u);
  BOOST_TEST(hits > rays.size() / 4);
}

BOOST_AUTO_TEST_CASE(a_sole_identity_instance_is_walked_without_a_top_level) {
  // One static mesh: single rays walk its BVH from the root, with the reference's answers, the
  // packets' answers, and exactly the node visits of the object's own walk (a top level above
  // it would add its own).
  std::mt19937 rng(47);
  const TriangleMesh mesh = makeRandomTriangles(rng, 2000, -4.0f, 4.0f, 0.4f);
  Scene scene(optionsFor(AccelKind::Bvh, TopLevelKind::Bvh));
  scene.createInstance(scene.createObject(mesh));
  scene.commit();
  const std::vector<Ray> rays = makeRays(rng, scene.bounds(), 3000, mesh.positions);
  checkScene(scene, rays, "sole identity instance", 300);

  BOOST_TEST(packetMismatches(scene, rays) == 0u);
  const ObjectAccel& accel = *scene.objectAccel(0);
  std::size_t visitMismatches = 0;
  for (const Ray& r : rays) {
    Hit hit, objectHit;
    TraversalContext sceneCtx, objectCtx;
    scene.intersect(r, hit, sceneCtx);
    ObjectRay objectRay(r.origin, r.direction, r.tnear, r.tfar, 0, 0);
    accel.intersect(objectRay, objectHit, objectCtx);
    if (sceneCtx.nodeVisits != objectCtx.nodeVisits) ++visitMismatches;
  }
  BOOST_TEST(visitMismatches == 0u);

  // Occlusion through the same path, with the occluder hint of the previous ray in play.
  TraversalContext shadowCtx;
  std::size_t shadowMismatches = 0;
  for (const Ray& r : rays)
    if (scene.occluded(r, shadowCtx) != scene.occluded(r)) ++shadowMismatches;
  BOOST_TEST(shadowMismatches == 0u);
}

BOOST_AUTO_TEST_CASE(rays_entering_the_top_levels_box_at_its_edges_hit) {
  // Closest-hit rays from outside the top level's box test that box before the walk: the test
  // must keep every ray that meets the scene, also one that enters exactly through the box's
  // boundary. A box mesh whose faces are the scene box's faces (at coordinates whose slab
  // distances round) and a transformed sphere inside, so that the top level is walked (a sole
  // identity instance skips it). Rays from outside cross into the box through points of its
  // edges and corners, where two or three slabs' entry distances tie and rounding decides; as
  // they go on inside, the closed box mesh and the watertight triangle test give every one a
  // hit by that point (up to the rounding of the origin). Tested against a top-level box
  // shrunk by 10^-5 of its extent, 11 of these rays missed (by 10^-3, 955).
  std::mt19937 rng(61);
  const Vec3f lo{-1.3f, 0.7f, -2.9f}, hi{2.1f, 3.3f, 0.37f};
  Scene scene(optionsFor(AccelKind::Bvh, TopLevelKind::Bvh));
  scene.createInstance(scene.createObject(makeBox(lo, hi)));
  scene.createInstance(scene.createObject(makeIcosphere(1)),
                       Affine3d::translation({0.4, 2.0, -1.2}));
  scene.commit();
  const Box3f box = scene.bounds();
  BOOST_TEST((box.lower == lo && box.upper == hi));
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), spread(-1.0f, 1.0f);
  std::vector<Ray> rays;
  std::vector<float> targetT;
  for (int i = 0; i < 4000; ++i) {
    // A point of an edge (one coordinate free) or, one time in four, a corner; the direction
    // points inwards along every axis whose coordinate lies on a bound, often barely, so that
    // the ray skims the box's faces.
    const int freeAxis = i % 4 == 3 ? -1 : i % 3;
    Vec3f target, direction;
    for (int a = 0; a < 3; ++a) {
      if (a == freeAxis) {
        target[a] = lo[a] + unit(rng) * (hi[a] - lo[a]);
        direction[a] = spread(rng);
      } else {
        const bool upper = unit(rng) < 0.5f;
        target[a] = upper ? hi[a] : lo[a];
        // From nearly along the boundary (2^-12) to steeply in.
        direction[a] = (upper ? -1.0f : 1.0f) * std::exp2(-12.0f * unit(rng));
      }
    }
    Ray r;
    targetT.push_back(0.5f + 3.0f * unit(rng));
    r.origin = target - direction * targetT.back();
    r.direction = direction;
    rays.push_back(r);
  }
  std::size_t outside = 0, reached = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    outside += box.contains(rays[i].origin) ? 0 : 1;
    Hit hit;
    if (scene.intersect(rays[i], hit) && hit.t <= targetT[i] * 1.001f) ++reached;
  }
  BOOST_TEST(outside == rays.size());
  BOOST_TEST(reached == rays.size());
  BOOST_TEST(packetMismatches(scene, rays) == 0u);
  // Packets from outside take the same test lane by lane (PacketKernels::meetsOneBox). The rays
  // grouped by direction octant, so that whole packets share their signs and reach it, under
  // every kernel set this CPU runs. Against a box shrunk by 10^-5 of its extent in the packet
  // test alone, 11 of them differed from the single rays with each kernel set.
  std::vector<Ray> grouped = rays;
  const auto octant = [](const Ray& r) {
    return (r.direction.x < 0.0f ? 1 : 0) + (r.direction.y < 0.0f ? 2 : 0) +
           (r.direction.z < 0.0f ? 4 : 0);
  };
  std::stable_sort(grouped.begin(), grouped.end(),
                   [&](const Ray& a, const Ray& b) { return octant(a) < octant(b); });
  IsaGuard guard;
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    BOOST_TEST(packetMismatches(scene, grouped) == 0u, simdIsaName(isa));
  }
}

BOOST_AUTO_TEST_CASE(refit_equals_rebuild_after_vertex_moves) {
  std::mt19937 rng(25);
  const TriangleMesh base = makeTorus(2.0, 0.6, 96, 48);  // 9216 triangles: parallel refit path
  const auto refitted = built(AccelKind::BvhFast, base);
  const double builtCost = refitted->stats().sahCost;
  BOOST_TEST(builtCost > 0.0);
  BOOST_TEST(refitted->stats().buildSahCost == builtCost);
  for (const float amount : {0.05f, 0.2f, 0.6f}) {
    const TriangleMesh mesh = deformed(base, amount);
    BOOST_TEST(refitted->refit(mesh));
    const BuildStats& st = refitted->stats();
    BOOST_TEST(st.refitted);
    BOOST_TEST(st.buildSahCost == builtCost);  // still the last full build's figure
    BOOST_TEST(st.sahCost > 0.0);
    BOOST_TEST(containsTriangles(refitted->bounds(), mesh));
    const auto rebuilt = built(AccelKind::BvhFast, mesh);
    BOOST_TEST(!rebuilt->stats().refitted);
    BOOST_TEST((refitted->bounds() == rebuilt->bounds()));
    const std::vector<Ray> rays = makeRays(rng, mesh.bounds(), 6000, mesh.positions);
    std::string first;
    const MeshReference reference(mesh);
    BOOST_TEST(countDifferences(*refitted, *rebuilt, rays, first, &reference) == 0u, first);
    BOOST_TEST(countDifferences(*refitted, *built(AccelKind::SahKdTree, mesh), rays, first,
                                &reference) == 0u,
               first);
  }
}

BOOST_AUTO_TEST_CASE(refit_through_collapse_to_a_point_and_back) {
  // Hard case 19: the mesh collapses to a line, then a point, then expands; the refitted tree
  // must contain every moved triangle at every step.
  const TriangleMesh sphere = makeIcosphere(2);
  const auto accel = built(AccelKind::BvhFast, sphere);
  std::mt19937 rng(26);
  for (const int step : {0, 1, 2, 3}) {
    TriangleMesh mesh = sphere;
    for (Vec3f& p : mesh.positions) {
      if (step == 0) p = {p.x, 0.0f, 0.0f};             // a segment
      if (step == 1) p = {0.25f, 0.25f, 0.25f};         // a point
      if (step == 2) p = p * 3.0f;                      // expanded again
      if (step == 3) p = p + Vec3f{10.0f, 0.0f, 0.0f};  // and moved away
    }
    BOOST_TEST(accel->refit(mesh));
    BOOST_TEST(accel->stats().degenerate == (step < 2 ? mesh.triangleCount() : 0u));
    BOOST_TEST(containsTriangles(accel->bounds(), mesh));
    const std::vector<Ray> rays = makeRays(rng, Box3f({-4, -4, -4}, {4, 4, 4}), 2000);
    std::string first;
    const MeshReference reference(mesh);
    BOOST_TEST(
        countDifferences(*accel, *built(AccelKind::SahKdTree, mesh), rays, first, &reference) == 0u,
        "step " << step << ": " << first);
  }
}

BOOST_AUTO_TEST_CASE(refit_is_refused_when_it_cannot_apply) {
  const TriangleMesh mesh = makeIcosphere(1);
  TriangleMesh otherTopology = mesh;
  std::swap(otherTopology.indices[0], otherTopology.indices[1]);
  TriangleMesh fewer = mesh;
  fewer.indices.resize(fewer.indices.size() - 3);
  const auto fast = built(AccelKind::BvhFast, mesh);
  BOOST_TEST(!fast->refit(otherTopology));
  BOOST_TEST(!fast->refit(fewer));
  BOOST_TEST(!fast->stats().refitted);
  BOOST_TEST(fast->refit(mesh));
  // The high-quality kinds rebuild instead.
  for (AccelKind kind : {AccelKind::Bvh, AccelKind::SahKdTree, AccelKind::FastKdTree})
    BOOST_TEST(!built(kind, mesh)->refit(mesh), accelKindName(kind));
}

BOOST_AUTO_TEST_CASE(scene_refits_deforming_objects_while_the_tree_stays_good) {
  SceneOptions options = optionsFor(AccelKind::Bvh);
  options.deformingAccel = AccelKind::BvhFast;
  Scene scene(options);
  const TriangleMesh base = makeTorus(2.0, 0.6, 48, 24);
  const ObjectId deforming = scene.createObject(base, ObjectUsage::Deforming);
  const ObjectId rigid = scene.createObject(makeIcosphere(2), ObjectUsage::Rigid);
  scene.createInstance(deforming);
  const InstanceId moving = scene.createInstance(rigid, Affine3d::translation({5, 0, 0}));
  CommitStats stats = scene.commit();
  BOOST_TEST(stats.objectsRebuilt == 2u);
  BOOST_TEST(stats.objectsRefitted == 0u);
  std::mt19937 rng(27);

  // Small moves: refitted, and the answers stay exact.
  for (int frame = 1; frame <= 3; ++frame) {
    scene.setObjectPositions(deforming, deformed(base, 0.05f * frame).positions);
    scene.setInstanceTransform(moving, Affine3d::translation({5, 0.1 * frame, 0}));
    stats = scene.commit();
    BOOST_TEST(stats.objectsRefitted == 1u);
    BOOST_TEST(stats.objectsRebuilt == 0u);
    BOOST_TEST(stats.trianglesRebuilt == base.triangleCount());
    BOOST_TEST(scene.objectAccel(deforming)->stats().refitted);
    checkScene(scene, makeRays(rng, scene.bounds(), 1500), "frame " + std::to_string(frame));
  }

  // Scrambled vertices: the refitted boxes overlap so much that the tree is rebuilt.
  TriangleMesh scrambled = base;
  std::shuffle(scrambled.positions.begin(), scrambled.positions.end(), rng);
  scene.setObjectPositions(deforming, scrambled.positions);
  stats = scene.commit();
  BOOST_TEST(stats.objectsRebuilt == 1u);
  BOOST_TEST(stats.objectsRefitted == 0u);
  const BuildStats& st = scene.objectAccel(deforming)->stats();
  BOOST_TEST(!st.refitted);
  BOOST_TEST(st.sahCost == st.buildSahCost);
  checkScene(scene, makeRays(rng, scene.bounds(), 1500), "scrambled");

  // New topology: rebuilt.
  TriangleMesh other = makeIcosphere(1);
  scene.setObjectMesh(deforming, other);
  stats = scene.commit();
  BOOST_TEST(stats.objectsRebuilt == 1u);
  BOOST_TEST(stats.objectsRefitted == 0u);
  checkScene(scene, makeRays(rng, scene.bounds(), 1500), "new topology");

  // The kd-trees never refit.
  Scene kd(sceneOptionsFor(Engine::KdTree));
  const ObjectId kdObject = kd.createObject(base, ObjectUsage::Deforming);
  kd.createInstance(kdObject);
  kd.commit();
  kd.setObjectPositions(kdObject, deformed(base, 0.05f).positions);
  stats = kd.commit();
  BOOST_TEST(stats.objectsRebuilt == 1u);
  BOOST_TEST(stats.objectsRefitted == 0u);
}

BOOST_AUTO_TEST_CASE(degenerate_triangles_never_hit) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  m.indices = {0, 1, 2,   // collinear
               0, 0, 3,   // repeated vertex
               0, 4, 1,   // zero area (0 and 4 coincide)
               0, 1, 3};  // the only real triangle
  TriangleMesh allDegenerate;
  allDegenerate.positions = m.positions;
  allDegenerate.indices = {0, 1, 2, 0, 0, 3, 0, 4, 1};
  for (AccelKind kind : kBvhKinds) {
    Scene scene(optionsFor(kind));
    const ObjectId obj = scene.createObject(m);
    scene.createInstance(obj);
    scene.createInstance(scene.createObject(allDegenerate), Affine3d::translation({0, 0, -1}));
    scene.commit();
    BOOST_TEST(scene.objectAccel(obj)->stats().degenerate == 3u);
    // The SAH tree leaves them out; the refittable tree keeps them for later frames.
    BOOST_TEST(scene.objectAccel(obj)->stats().primReferences ==
               (kind == AccelKind::Bvh ? 1u : 4u));
    BOOST_TEST((scene.objectAccel(obj)->bounds() == Box3f({0, 0, 0}, {1, 1, 0})));
    std::mt19937 rng(28);
    std::uniform_real_distribution<float> u(-0.5f, 2.5f);
    std::size_t hits = 0, wrong = 0;
    for (int i = 0; i < 5000; ++i) {
      Ray r{{u(rng), u(rng), 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, kInfinity};
      if (i % 2) r.direction = {u(rng), u(rng), -1.0f};
      Hit hit;
      if (scene.intersect(r, hit)) {
        ++hits;
        wrong += hit.primId != 3u || hit.instanceId != 0u;
      }
    }
    BOOST_TEST(hits > 0u);
    BOOST_TEST(wrong == 0u);
  }
}

BOOST_AUTO_TEST_CASE(nearly_degenerate_triangles_are_classified_exactly) {
  // The refittable tree classifies degenerate triangles with a float shortcut: slivers one ulp
  // off a line, tiny and huge coordinates (underflowing and overflowing products) must be
  // counted exactly as the exact test counts them, at build and at refit. (Coordinates stay
  // finite: the binned SAH builder does not take infinite vertices.)
  TriangleMesh m;
  const float ulp = std::nextafter(2.0f, 3.0f);
  const float scales[] = {1.0f, 1e-20f, 1e-38f, 1e15f, 1e30f, 1e38f};
  for (float s : scales) {
    const std::vector<Vec3f> tri[] = {
        {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}},        // collinear
        {{0, 0, 0}, {1, 1, 1}, {2, 2, ulp}},      // one ulp off the line
        {{1, 1, 1}, {1, 1, 1}, {2, 3, 4}},        // repeated vertex
        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},        // a real triangle
        {{-1, 2, 0}, {1, -2, 0}, {3, -6, 0.0f}},  // collinear through the origin
    };
    for (const auto& t : tri) {
      for (const Vec3f& p : t) {
        m.positions.push_back(p * s);
        m.indices.push_back(static_cast<std::uint32_t>(m.indices.size()));
      }
    }
  }
  std::size_t expected = 0;
  for (std::size_t i = 0; i < m.indices.size(); i += 3)
    expected += isDegenerateTriangle(m.positions[i], m.positions[i + 1], m.positions[i + 2]);
  BOOST_TEST(expected >= 2 * std::size(scales));
  const auto fast = built(AccelKind::BvhFast, m);
  BOOST_TEST(fast->stats().degenerate == expected);
  BOOST_TEST(built(AccelKind::Bvh, m)->stats().degenerate == expected);
  BOOST_TEST(fast->refit(m));
  BOOST_TEST(fast->stats().degenerate == expected);
}

BOOST_AUTO_TEST_CASE(zero_and_negative_zero_direction_components) {
  for (AccelKind kind : kBvhKinds) {
    for (TopLevelKind topLevel : kTopLevels) {
      Scene scene(optionsFor(kind, topLevel));
      scene.createInstance(scene.createObject(makeBox({0, 0, 0}, {1, 1, 1})));
      scene.createInstance(scene.createObject(makeBox({1, 0, 0}, {2, 1, 1})));
      // A grid of boxes sharing faces, in one object: inner BVH boxes share planes too.
      TriangleMesh grid;
      for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 4; ++y) {
          const TriangleMesh cell = makeBox({float(x), float(y), 3.0f}, {x + 1.0f, y + 1.0f, 4.0f});
          const auto base = static_cast<std::uint32_t>(grid.positions.size());
          grid.positions.insert(grid.positions.end(), cell.positions.begin(), cell.positions.end());
          for (std::uint32_t i : cell.indices) grid.indices.push_back(base + i);
        }
      scene.createInstance(scene.createObject(grid));
      scene.commit();
      std::vector<Ray> rays;
      const float zeros[] = {0.0f, -0.0f};
      // Origins on face planes (x, y in {0, 1, 2, ...}) and between them, axis directions.
      for (float x : {0.0f, 0.5f, 1.0f, 1.5f, 2.0f, 3.0f, 4.0f})
        for (float y : {0.0f, 0.25f, 1.0f, 2.0f, 4.0f})
          for (float z0 : zeros)
            for (float z1 : zeros) {
              rays.push_back({{x, y, -5.0f}, 0.0f, {z0, z1, 1.0f}, kInfinity});
              rays.push_back({{x, y, 9.0f}, 0.0f, {z1, z0, -1.0f}, kInfinity});
              rays.push_back({{x, -5.0f, 0.5f}, 0.0f, {z0, 1.0f, z1}, kInfinity});
              rays.push_back({{x, -5.0f, 3.0f}, 0.0f, {z0, 1.0f, z1}, kInfinity});
              rays.push_back({{-5.0f, y, 0.5f}, 0.0f, {1.0f, z0, z1}, kInfinity});
              rays.push_back({{9.0f, y, 4.0f}, 0.0f, {-1.0f, z0, z1}, kInfinity});
            }
      std::size_t nanSeen = 0;
      for (const Ray& r : rays) {
        Hit hit;
        if (scene.intersect(r, hit) && (std::isnan(hit.t) || std::isnan(hit.u))) ++nanSeen;
      }
      BOOST_TEST(nanSeen == 0u);
      // Most of these rays lie in face planes, which the reference calls ambiguous.
      checkScene(scene, rays, "+-0 " + nameOf(kind, topLevel), 20);
    }
  }
}

BOOST_AUTO_TEST_CASE(rays_from_inside_closed_meshes_never_leak) {
  const TriangleMesh meshes[] = {makeIcosphere(5), makeBox({-1, -1, -1}, {1, 1, 1}),
                                 makeTorus(2.0, 0.7, 48, 24)};
  const Vec3f origins[] = {{0.01f, -0.02f, 0.03f}, {0.1f, 0.2f, -0.3f}, {2.0f, 0.0f, 0.1f}};
  BOOST_TEST(meshes[0].triangleCount() >= 20000u);
  for (AccelKind kind : kBvhKinds) {
    for (int m = 0; m < 3; ++m) {
      Scene scene(optionsFor(kind));
      scene.createInstance(scene.createObject(meshes[m]));
      scene.commit();
      const TriangleMesh& mesh = meshes[m];
      std::size_t rays = 0, leaks = 0, occlusionLeaks = 0;
      auto shoot = [&](const Vec3f& target) {
        const Ray r{origins[m], 0.0f, target - origins[m], kInfinity};
        ++rays;
        Hit hit;
        if (!scene.intersect(r, hit)) ++leaks;
        if (!scene.occluded(r)) ++occlusionLeaks;
      };
      // Exactly at every vertex and at points on every edge (barycentrics 0 and 1 in float).
      for (const Vec3f& v : mesh.positions) shoot(v);
      for (std::size_t i = 0; i < mesh.indices.size(); i += 3)
        for (int e = 0; e < 3; ++e) {
          const Vec3f a = mesh.positions[mesh.indices[i + e]];
          const Vec3f b = mesh.positions[mesh.indices[i + (e + 1) % 3]];
          shoot((a + b) * 0.5f);
          shoot(a + (b - a) * 0.25f);
        }
      BOOST_TEST_MESSAGE(accelKindName(kind)
                         << " mesh " << m << ": " << leaks << " leaks in " << rays << " rays");
      BOOST_TEST(leaks == 0u);
      BOOST_TEST(occlusionLeaks == 0u);
    }
  }
}

BOOST_AUTO_TEST_CASE(empty_meshes) {
  const TriangleMesh empty;
  for (AccelKind kind : kBvhKinds) {
    const auto accel = built(kind, empty);
    BOOST_TEST(accel->bounds().empty());
    BOOST_TEST(accel->stats().triangles == 0u);
    BOOST_TEST(accel->stats().sahCost == 0.0);
    const Ray r{{0, 0, -1}, 0.0f, {0, 0, 1}, kInfinity};
    const ObjectAnswer a = query(*accel, r);
    BOOST_TEST(!a.hit);
    BOOST_TEST(!a.occluded);
    BOOST_TEST(accel->refit(empty) == (kind == AccelKind::BvhFast));

    for (TopLevelKind topLevel : kTopLevels) {
      Scene scene(optionsFor(kind, topLevel));
      const ObjectId e = scene.createObject(empty, ObjectUsage::Deforming);
      scene.createInstance(e);
      scene.commit();
      Hit hit;
      BOOST_TEST(!scene.intersect(r, hit));
      BOOST_TEST(!scene.occluded(r));
      // Empty, then something, then empty again.
      scene.setObjectMesh(e, makeBox());
      scene.commit();
      BOOST_TEST(scene.intersect({{0.5f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, kInfinity}, hit));
      scene.setObjectMesh(e, empty);
      scene.commit();
      BOOST_TEST(!scene.intersect({{0.5f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, kInfinity}, hit));
    }
    // A top level over no instances at all.
    Scene none(optionsFor(kind));
    none.commit();
    Hit hit;
    BOOST_TEST(!none.intersect(r, hit));
  }
}

BOOST_AUTO_TEST_CASE(one_triangle_meshes_and_inclusive_interval_ends) {
  for (AccelKind kind : kBvhKinds) {
    for (TopLevelKind topLevel : kTopLevels) {
      Scene scene(optionsFor(kind, topLevel));
      const ObjectId id = scene.createObject(intervalTriangle());
      scene.createInstance(id);
      scene.commit();
      BOOST_TEST(scene.objectAccel(id)->stats().leaves == 1u);
      checkInclusiveIntervalEnds(scene);
      Hit hit;
      // Through a vertex, with a -0 direction component.
      BOOST_TEST(scene.intersect({{0, 1, 0}, 0.0f, {-0.0f, 0.0f, 1}, kInfinity}, hit));
      // Huge and infinite tfar.
      for (float tfar : {kInfinity, std::numeric_limits<float>::max()}) {
        BOOST_TEST(scene.intersect({{0, 0, 0}, 0.0f, {0, 0, 1}, tfar}, hit));
        BOOST_TEST(hit.t == 5.0f);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(coincident_and_touching_instances) {
  for (AccelKind kind : {AccelKind::SahKdTree, AccelKind::Bvh}) {
    Scene coincident(optionsFor(kind, TopLevelKind::Bvh));
    const ObjectId sphere = coincident.createObject(makeIcosphere(0));
    for (int i = 0; i < 1000; ++i)
      coincident.createInstance(sphere, Affine3d::translation({3, 3, 3}));
    coincident.commit();
    BOOST_TEST(coincident.topLevel().stats().maxDepth <= 64u);
    BOOST_TEST(coincident.topLevel().stats().references == 1000u);
    std::mt19937 rng(29);
    const std::vector<Ray> rays = makeRays(rng, coincident.bounds(), 200);
    checkScene(coincident, rays, "1000 coincident " + std::string(accelKindName(kind)));
    // The tie rule picks the lowest instance id, as the kd top level does.
    for (const Ray& r : rays) {
      Hit hit;
      if (coincident.intersect(r, hit)) BOOST_TEST(hit.instanceId == 0u);
    }

    Scene touching(optionsFor(kind, TopLevelKind::Bvh));
    const ObjectId box = touching.createObject(makeBox());
    for (int x = 0; x < 10; ++x)
      for (int y = 0; y < 10; ++y)
        for (int z = 0; z < 3; ++z)
          touching.createInstance(box, Affine3d::translation({double(x), double(y), double(z)}));
    touching.commit();
    BOOST_TEST(touching.topLevel().stats().maxDepth <= 64u);
    BOOST_TEST(touching.topLevel().stats().leaves > 1u);
    checkScene(touching, makeRays(rng, touching.bounds(), 1500),
               "touching " + std::string(accelKindName(kind)), 100);
  }
}

BOOST_AUTO_TEST_CASE(builds_do_not_depend_on_the_thread_count) {
  std::mt19937 rng(30);
  const TriangleMesh mesh = makeRandomTriangles(rng, 20000, -10.0f, 10.0f, 0.8f);
  const std::vector<Ray> rays = makeRays(rng, mesh.bounds(), 3000);
  for (AccelKind kind : kBvhKinds) {
    std::unique_ptr<ObjectAccel> one, two;
    tbb::task_arena(1).execute([&] { one = built(kind, mesh); });
    tbb::task_arena(2).execute([&] { two = built(kind, mesh); });
    BOOST_TEST(one->stats().nodes == two->stats().nodes);
    BOOST_TEST(one->stats().leaves == two->stats().leaves);
    BOOST_TEST(one->stats().maxDepth == two->stats().maxDepth);
    BOOST_TEST(one->stats().sahCost == two->stats().sahCost);
    std::string first;
    BOOST_TEST(countDifferences(*one, *two, rays, first) == 0u, first);
  }
}

BOOST_AUTO_TEST_CASE(static_trees_hold_the_memory_they_use) {
  // A static tree is built once and kept for many frames: it must not keep the builder's worst
  // case (one node per triangle) but about what it uses. A four-wide node takes 128 bytes, a
  // triangle reference 36 (its vertices, as leaf rows) plus 4 (its mesh index) plus 1 (its
  // place in its leaf); the rows end in a few floats of padding. With AVX2 or AVX-512 the tree
  // also keeps an eight-wide copy of its nodes, 256 bytes each and fewer than the four-wide ones.
  IsaGuard guard;
  std::mt19937 rng(31);
  const TriangleMesh mesh = makeRandomTriangles(rng, 20000, -10.0f, 10.0f, 0.8f);
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    const std::unique_ptr<ObjectAccel> accel = built(AccelKind::Bvh, mesh);
    const BuildStats& s = accel->stats();
    const std::size_t innerNodes = s.nodes - s.leaves;
    BOOST_TEST(innerNodes < s.triangles / 2);
    if (isa == SimdIsa::Portable) {
      BOOST_TEST(s.wideNodes == 0u);
    } else {
      BOOST_TEST(s.wideNodes > innerNodes / 4);
      BOOST_TEST(s.wideNodes < innerNodes * 3 / 4);
    }
    const std::size_t used = innerNodes * 128 + s.wideNodes * 256 + s.primReferences * (36 + 4 + 1);
    BOOST_TEST(s.bytes >= used);
    BOOST_TEST(s.bytes <= used + innerNodes * 128 / 4);
  }
}

BOOST_AUTO_TEST_CASE(wide_top_level_walk_gives_the_four_wide_walks_hits) {
  // The top level is committed once per SIMD kernel set: with AVX2 or AVX-512, rays from inside
  // it walk its eight-wide twins (Bvh8Walk.h); with the portable kernels, the BVH4. Every
  // answer must be the same bits, and the wide walk must actually run (fewer node visits),
  // for closest hits and, the top level being deep enough, for any hits.
  IsaGuard guard;
  std::mt19937 rng(404);
  const TriangleMesh flat = makeRandomTriangles(rng, 600, -12.0f, 12.0f, 1.5f);
  std::vector<TriangleMesh> parts;
  for (int o = 0; o < 4; ++o) parts.push_back(makeRandomTriangles(rng, 80, -2.0f, 2.0f, 0.8f));
  std::vector<Affine3d> placements;
  for (int i = 0; i < 240; ++i) placements.push_back(randomTransform(rng, 12.0, true));
  std::vector<std::vector<Hit>> answers;
  std::vector<std::vector<std::uint8_t>> blocked;
  std::vector<std::uint64_t> visits, anyHitVisits;
  std::vector<Ray> rays, segments;
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    Scene scene(optionsFor(AccelKind::Bvh));
    scene.createInstance(scene.createObject(flat));
    std::vector<ObjectId> ids;
    for (const TriangleMesh& part : parts)
      ids.push_back(scene.createObject(part, ObjectUsage::Rigid));
    for (std::size_t i = 0; i < placements.size(); ++i)
      scene.createInstance(ids[i % ids.size()], placements[i]);
    scene.commit();
    if (rays.empty()) {
      // Origins inside the scene (the wide walk's rays) and around it (the four-wide walk's).
      rays = makeRays(rng, scene.bounds(), 4000);
      std::uniform_real_distribution<float> u(-1.0f, 1.0f);
      const Vec3f c = scene.bounds().center(), e = scene.bounds().extent();
      for (int i = 0; i < 4000; ++i) {
        Ray r;
        r.origin = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.45f;
        r.direction = {u(rng), u(rng), u(rng)};
        rays.push_back(r);
      }
    }
    TraversalContext ctx;
    std::vector<Hit>& hits = answers.emplace_back(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) scene.intersect(rays[i], hits[i], ctx);
    visits.push_back(ctx.nodeVisits);
    if (isa == SimdIsa::Portable) {
      // Judged against the double reference on every fourth ray (its cost grows with the
      // instances, which the any-hit walk needs many of for a deep top level).
      std::vector<Ray> judged;
      for (std::size_t i = 0; i < rays.size(); i += 4) judged.push_back(rays[i]);
      checkScene(scene, judged, "portable top level", 50);
    }
    // Any hits: each ray cut at a random end, so that about half are blocked. A fresh context
    // per query keeps the occluder hint of the previous one out of the walk.
    BOOST_TEST_REQUIRE(scene.topLevel().stats().maxDepth >= 5u);
    if (segments.empty()) {
      std::uniform_real_distribution<float> cut(0.0f, 2.0f);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits[i].valid()) continue;
        Ray r = rays[i];
        r.tfar = hits[i].t * cut(rng);
        segments.push_back(r);
      }
    }
    std::vector<std::uint8_t>& occluded = blocked.emplace_back(segments.size());
    std::uint64_t anyHitNodes = 0;
    for (std::size_t i = 0; i < segments.size(); ++i) {
      TraversalContext fresh;
      occluded[i] = scene.occluded(segments[i], fresh) ? 1 : 0;
      anyHitNodes += fresh.nodeVisits;
      // The closest hit along the same segment decides the any-hit answer.
      Hit closest;
      scene.intersect(segments[i], closest, fresh);
      BOOST_TEST(occluded[i] == (closest.valid() ? 1 : 0), "segment " << i);
    }
    anyHitVisits.push_back(anyHitNodes);
  }
  std::size_t blockedCount = 0;
  for (std::uint8_t b : blocked.front()) blockedCount += b;
  BOOST_TEST(blockedCount > segments.size() / 4);
  BOOST_TEST(blockedCount < segments.size() * 3 / 4);
  std::size_t found = 0;
  for (const Hit& h : answers.front()) found += h.valid() ? 1 : 0;
  BOOST_TEST(found > rays.size() / 4);
  for (std::size_t k = 1; k < answers.size(); ++k) {
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
      mismatches += sameHitBits(answers[k][i], answers[0][i]) ? 0 : 1;
    BOOST_TEST(mismatches == 0u, "kernel set " << k << " differs on " << mismatches << " rays");
    BOOST_TEST(visits[k] < visits[0], "kernel set " << k << ": " << visits[k] << " node visits, "
                                                    << "portable " << visits[0]);
    BOOST_TEST((blocked[k] == blocked[0]), "kernel set " << k << ": any-hit answers differ");
    BOOST_TEST(anyHitVisits[k] < anyHitVisits[0], "kernel set " << k << ": " << anyHitVisits[k]
                                                                << " any-hit node visits, "
                                                                << "portable " << anyHitVisits[0]);
  }
}

BOOST_AUTO_TEST_CASE(whole_object_walks_through_the_wide_tree_give_the_four_wide_hits) {
  // An object BVH built with AVX2 or AVX-512 active is walked whole by single rays through its
  // eight-wide copy; built with the portable kernels, through the BVH4. Every closest hit and
  // any-hit answer must be the same bits, and the wide walk must actually run (fewer visits).
  // Rays start inside and around the meshes; segments cut at random ends are about half
  // blocked, and a mesh of one triangle has a one-slot wide tree.
  IsaGuard guard;
  std::mt19937 rng(808);
  for (const std::size_t n : {1u, 7u, 300u, 5000u}) {
    const TriangleMesh mesh = makeRandomTriangles(rng, n, -6.0f, 6.0f, 1.2f);
    std::vector<Ray> rays;
    std::vector<ObjectAnswer> portable;
    std::uint64_t portableVisits = 0;
    for (SimdIsa isa : supportedSimdIsas()) {
      BOOST_REQUIRE(setSimdIsa(isa));
      const std::unique_ptr<ObjectAccel> accel = built(AccelKind::Bvh, mesh);
      BOOST_TEST((accel->stats().wideNodes > 0u) == (isa != SimdIsa::Portable));
      if (rays.empty()) {
        rays = makeRays(rng, accel->bounds(), 3000, mesh.positions);
        std::uniform_real_distribution<float> cut(0.0f, 2.0f);
        for (std::size_t i = 0; i < rays.size(); i += 2) rays[i].tfar = cut(rng) * 12.0f;
      }
      std::uint64_t visits = 0;
      std::size_t mismatches = 0, blockedMismatches = 0, hits = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        TraversalContext ctx;
        ObjectRay ray(rays[i].origin, rays[i].direction, rays[i].tnear, rays[i].tfar, 0, 0);
        ObjectAnswer a;
        a.hit = accel->intersect(ray, a.record, ctx);
        a.occluded = accel->occluded(
            ObjectRay(rays[i].origin, rays[i].direction, rays[i].tnear, rays[i].tfar, 0, 0), ctx);
        visits += ctx.nodeVisits;
        hits += a.hit ? 1 : 0;
        // The closest hit decides the any-hit answer.
        BOOST_TEST(a.occluded == a.hit, "ray " << i << " of " << n << " triangles");
        if (isa == SimdIsa::Portable) {
          portable.push_back(a);
        } else {
          mismatches +=
              (a.hit == portable[i].hit && sameHitBits(a.record, portable[i].record)) ? 0 : 1;
          blockedMismatches += a.occluded == portable[i].occluded ? 0 : 1;
        }
      }
      if (isa == SimdIsa::Portable) {
        portableVisits = visits;
        BOOST_TEST(hits > rays.size() / 8, n << " triangles: " << hits << " hits");
        continue;
      }
      BOOST_TEST(mismatches == 0u, simdIsaName(isa) << ", " << n << " triangles: " << mismatches
                                                    << " closest hits differ");
      BOOST_TEST(blockedMismatches == 0u, simdIsaName(isa)
                                              << ", " << n << " triangles: " << blockedMismatches
                                              << " any-hit answers differ");
      if (n >= 300)
        BOOST_TEST(visits < portableVisits, simdIsaName(isa)
                                                << ": " << visits << " node visits, portable "
                                                << portableVisits);
    }
  }
}
