// Ray packets (Scene::intersect and Scene::occluded over spans) give bit for bit the answers of
// single rays, with every SIMD kernel this CPU runs, under both engines, on random flat and
// instanced scenes with coherent, incoherent, axis-parallel (+-0) and untraceable rays; they
// agree with the double-precision reference and do not leak through closed meshes (hard case
// 22, fast-engine issue).
#define BOOST_TEST_MODULE packet
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <memory>

#include "IsaGuard.h"
#include "PacketKernel.h"
#include "PacketObjectRays.h"
#include "PacketTransformedRays.h"
#include "TestGeometry.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/Simd.h"

using namespace tg;
using namespace tg::test;

namespace {

/// Engine configurations: the BVH engine (packet walks at both levels), BVH objects of the
/// refittable kind, kd-tree objects under the BVH top level (packets at the top only), and the
/// kd engine (every lane alone).
struct Config {
  const char* name;
  SceneOptions options;
};

std::vector<Config> configs() {
  SceneOptions fast = sceneOptionsFor(Engine::Bvh);
  fast.staticAccel = AccelKind::BvhFast;
  SceneOptions mixed = sceneOptionsFor(Engine::Bvh);
  mixed.staticAccel = AccelKind::SahKdTree;
  return {{"bvh", sceneOptionsFor(Engine::Bvh)},
          {"bvh-fast", fast},
          {"sah-kd/bvh", mixed},
          {"kd", sceneOptionsFor(Engine::KdTree)}};
}

/// Counts of one packets-against-single-rays comparison.
struct Comparison {
  std::size_t rays = 0, hits = 0, occluded = 0, mismatches = 0;
  std::uint64_t packetNodeVisits = 0, singleNodeVisits = 0;
  std::string firstMismatch;
};

Comparison compareWithSingleRays(const Scene& scene, const std::vector<Ray>& rays) {
  Comparison c;
  std::vector<Hit> hits(rays.size());
  std::vector<std::uint8_t> blocked(rays.size());
  TraversalContext packetCtx, singleCtx;
  scene.intersect(std::span<const Ray>(rays), std::span<Hit>(hits), packetCtx);
  scene.occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(blocked), packetCtx);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    const bool got = scene.intersect(rays[i], single, singleCtx);
    const bool occ = scene.occluded(rays[i], singleCtx);
    ++c.rays;
    c.hits += got ? 1 : 0;
    c.occluded += occ ? 1 : 0;
    const bool same =
        sameHitBits(hits[i], single) && hits[i].valid() == got && (blocked[i] != 0) == occ;
    if (!same && c.mismatches++ == 0)
      c.firstMismatch = "ray " + std::to_string(i) + " " + describe(rays[i]) + ": packet t " +
                        std::to_string(hits[i].t) + " prim " + std::to_string(hits[i].primId) +
                        " occluded " + std::to_string(blocked[i]) + ", single t " +
                        std::to_string(single.t) + " prim " + std::to_string(single.primId) +
                        " occluded " + std::to_string(occ);
  }
  c.packetNodeVisits = packetCtx.nodeVisits;
  c.singleNodeVisits = singleCtx.nodeVisits;
  return c;
}

/// Camera-like packets: one origin, directions through a jittered grid of 8 x 8 points per
/// tile of a plane in front of the scene (coherent primary rays).
std::vector<Ray> cameraRays(std::mt19937& rng, const Box3f& box, int tiles) {
  std::vector<Ray> rays;
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec3f c = box.center(), e = box.extent();
  for (int t = 0; t < tiles; ++t) {
    const Vec3f eye = c + Vec3f{u(rng), u(rng), u(rng)} * (1.5f * maxComponent(e) + 1.0f);
    const Vec3f look = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.4f;
    const Vec3f forward = normalize(look - eye);
    const Vec3f side =
        normalize(cross(forward, std::abs(forward.y) < 0.9f ? Vec3f{0, 1, 0} : Vec3f{1, 0, 0}));
    const Vec3f up = cross(side, forward);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        Ray r;
        r.origin = eye;
        r.direction = normalize(forward + side * (0.01f * (x - 3.5f)) + up * (0.01f * (y - 3.5f)));
        rays.push_back(r);
      }
  }
  return rays;
}

/// Camera-like tiles of 64 rays whose directions all lie in octant `signs` (bit a set: component
/// a negative): eyes beyond the box on the opposite side of every axis, aimed at points inside.
/// The packet walks are compiled once per octant, so each one is tested with rays of its own.
std::vector<Ray> octantRays(std::mt19937& rng, const Box3f& box, unsigned signs, int tiles) {
  std::vector<Ray> rays;
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), beyond(1.2f, 2.0f);
  const Vec3f c = box.center(), e = box.extent();
  for (int t = 0; t < tiles; ++t) {
    Vec3f eye = c;
    for (int a = 0; a < 3; ++a) {
      const float side = ((signs >> a) & 1u) != 0 ? 1.0f : -1.0f;  // where the rays come from
      eye[a] += side * (beyond(rng) * 0.5f * e[a] + 1.0f);
    }
    const Vec3f look = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.3f;
    for (int k = 0; k < 64; ++k) {
      const Vec3f target = look + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.1f;
      Ray r;
      r.origin = eye;
      r.direction = normalize(target - eye);
      rays.push_back(r);
    }
  }
  return rays;
}

/// Shadow-like packets: origins scattered in the scene, all aimed at one light point, with
/// tfar just short of the light.
std::vector<Ray> shadowRays(std::mt19937& rng, const Box3f& box, int packets) {
  std::vector<Ray> rays;
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec3f c = box.center(), e = box.extent();
  for (int p = 0; p < packets; ++p) {
    const Vec3f light = c + Vec3f{u(rng), u(rng), u(rng)} * maxComponent(e);
    const Vec3f spot = c + Vec3f{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * 0.4f;
    for (int l = 0; l < 8; ++l) {
      Ray r;
      r.origin = spot + Vec3f{u(rng), u(rng), u(rng)} * (0.05f * maxComponent(e));
      r.direction = light - r.origin;
      r.tnear = 1e-4f;
      r.tfar = 0.999f;
      rays.push_back(r);
    }
  }
  return rays;
}

/// Rays the scene must reject (never hit), mixed into packets of good rays, and a stream
/// length that is not a multiple of the packet size.
void addUntraceableRays(std::vector<Ray>& rays) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 3; i < rays.size(); i += 29) {
    switch (i % 4) {
      case 0:
        rays[i].origin.x = nan;
        break;
      case 1:
        rays[i].direction = {0.0f, -0.0f, 0.0f};
        break;
      case 2:
        rays[i].tnear = rays[i].tfar + 1.0f;
        break;
      default:
        rays[i].direction.y = kInfinity;
        break;
    }
  }
  rays.resize(rays.size() - 3);
}

/// The same content in one scene per configuration: flat random triangles plus instances of
/// random objects under rotations, non-uniform scales and mirrorings.
std::vector<std::unique_ptr<Scene>> makeScenes(std::mt19937& rng, bool instanced) {
  std::vector<std::unique_ptr<Scene>> scenes;
  for (const Config& config : configs()) scenes.push_back(std::make_unique<Scene>(config.options));
  const TriangleMesh flat = makeRandomTriangles(rng, 800, -10.0f, 10.0f, 2.0f);
  for (auto& scene : scenes) scene->createInstance(scene->createObject(flat));
  if (instanced) {
    for (int o = 0; o < 3; ++o) {
      const TriangleMesh mesh = makeRandomTriangles(rng, 60, -2.0f, 2.0f, 1.0f);
      std::vector<ObjectId> ids;
      for (auto& scene : scenes) ids.push_back(scene->createObject(mesh, ObjectUsage::Rigid));
      for (int i = 0; i < 5; ++i) {
        const Affine3d m = randomTransform(rng, 12.0, true);
        for (std::size_t s = 0; s < scenes.size(); ++s) scenes[s]->createInstance(ids[s], m);
      }
      // Untransformed instances too: a packet walk shares the object rays of the identity
      // instances it enters, so hits must still carry each one's own ids.
      if (o < 2)
        for (std::size_t s = 0; s < scenes.size(); ++s) scenes[s]->createInstance(ids[s]);
    }
  }
  for (auto& scene : scenes) scene->commit();
  return scenes;
}

void checkAllKernels(bool instanced, unsigned seed) {
  IsaGuard guard;
  std::mt19937 rng(seed);
  const auto scenes = makeScenes(rng, instanced);
  const Box3f box = scenes.front()->bounds();
  std::vector<Ray> incoherentRays = makeRays(rng, box, 3000);
  addUntraceableRays(incoherentRays);
  const std::vector<Ray>& incoherent = incoherentRays;
  const std::vector<Ray> camera = cameraRays(rng, box, 30);
  const std::vector<Ray> shadow = shadowRays(rng, box, 200);
  const std::vector<Config> cs = configs();
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      const std::string label = std::string(instanced ? "instanced" : "flat") + " seed " +
                                std::to_string(seed) + " " + std::string(simdIsaName(isa)) + " " +
                                cs[s].name;
      for (const auto& [kind, rays] :
           {std::pair{"incoherent", &incoherent}, std::pair{"camera", &camera},
            std::pair{"shadow", &shadow}}) {
        const Comparison c = compareWithSingleRays(*scenes[s], *rays);
        BOOST_TEST_MESSAGE(label << " " << kind << ": " << c.rays << " rays, " << c.hits
                                 << " hits, " << c.occluded << " occluded, node visits packet "
                                 << c.packetNodeVisits << " single " << c.singleNodeVisits);
        BOOST_TEST(c.mismatches == 0u, label << " " << kind << ": " << c.firstMismatch);
        BOOST_TEST(c.hits > c.rays / 20, label << " " << kind << ": too few hits to mean anything");
        // The packet walk must actually run for coherent rays on BVHs: one node visit serves
        // every lane, so far fewer visits are counted than for single rays.
        if (std::string_view(kind) == "camera" && cs[s].options.topLevel == TopLevelKind::Bvh &&
            cs[s].options.staticAccel != AccelKind::SahKdTree)
          BOOST_TEST(c.packetNodeVisits * 2 < c.singleNodeVisits, label << " " << kind);
      }
    }
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(kernels_are_listed_and_selectable) {
  IsaGuard guard;
  const std::vector<SimdIsa> isas = supportedSimdIsas();
  BOOST_REQUIRE(!isas.empty());
  BOOST_TEST((isas.front() == SimdIsa::Portable));
  for (SimdIsa isa : isas) {
    BOOST_TEST(setSimdIsa(isa));
    BOOST_TEST((activeSimdIsa() == isa));
    BOOST_TEST((parseSimdIsa(simdIsaName(isa)) == isa));
  }
  BOOST_TEST(!parseSimdIsa("sse9").has_value());
}

BOOST_AUTO_TEST_CASE(packets_of_every_octant_equal_single_rays) {
  IsaGuard guard;
  std::mt19937 rng(808);
  const auto scenes = makeScenes(rng, true);
  const Box3f box = scenes.front()->bounds();
  const std::vector<Config> cs = configs();
  for (unsigned signs = 0; signs < 8; ++signs) {
    const std::vector<Ray> rays = octantRays(rng, box, signs, 4);
    for (const Ray& r : rays)
      for (int a = 0; a < 3; ++a)
        BOOST_REQUIRE((r.direction[a] < 0.0f) == (((signs >> a) & 1u) != 0));
    for (SimdIsa isa : supportedSimdIsas()) {
      BOOST_REQUIRE(setSimdIsa(isa));
      for (std::size_t s = 0; s < scenes.size(); ++s) {
        const std::string label = "octant " + std::to_string(signs) + " " +
                                  std::string(simdIsaName(isa)) + " " + cs[s].name;
        const Comparison c = compareWithSingleRays(*scenes[s], rays);
        BOOST_TEST(c.mismatches == 0u, label << ": " << c.firstMismatch);
        BOOST_TEST(c.hits > c.rays / 10, label << ": too few hits to mean anything");
        // Single rays walk eight-wide trees where the CPU runs AVX2, so each of their visits
        // tests as many boxes as two of a packet's: a packet walk that fell back to single
        // rays would count as many visits as they do, one that runs fewer than two thirds.
        if (cs[s].options.topLevel == TopLevelKind::Bvh &&
            cs[s].options.staticAccel != AccelKind::SahKdTree)
          BOOST_TEST(c.packetNodeVisits * 3 < c.singleNodeVisits * 2,
                     label << ": " << c.packetNodeVisits << " packet visits, " << c.singleNodeVisits
                           << " single-ray visits");
      }
    }
  }
}

/// Pairs of neighbouring packets walked as one (TraversalContext::pairPackets, where the active
/// kernels have pair walks) answer bit for bit as each packet walked alone, closest and any hit,
/// and visit fewer nodes with camera rays.
BOOST_AUTO_TEST_CASE(paired_packets_equal_packets_alone) {
  IsaGuard guard;
  std::mt19937 rng(1616);
  const auto scenes = makeScenes(rng, true);
  const std::vector<Config> cs = configs();
  const std::vector<Ray> rays = cameraRays(rng, scenes.front()->bounds(), 12);
  const std::size_t n = rays.size();
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    const detail::PacketKernels& kernels = detail::activePacketKernels();
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      const std::string label = std::string(simdIsaName(isa)) + " " + cs[s].name;
      std::vector<Hit> paired(n), alone(n);
      std::vector<std::uint8_t> pairedBlocked(n), aloneBlocked(n);
      TraversalContext pairedCtx, aloneCtx;
      aloneCtx.pairPackets = false;
      scenes[s]->intersect(std::span<const Ray>(rays), std::span<Hit>(paired), pairedCtx);
      scenes[s]->intersect(std::span<const Ray>(rays), std::span<Hit>(alone), aloneCtx);
      const std::uint64_t pairedClosest = pairedCtx.nodeVisits, aloneClosest = aloneCtx.nodeVisits;
      scenes[s]->occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(pairedBlocked),
                          pairedCtx);
      scenes[s]->occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(aloneBlocked),
                          aloneCtx);
      std::size_t mismatches = 0, hits = 0;
      for (std::size_t i = 0; i < n; ++i) {
        mismatches +=
            sameHitBits(paired[i], alone[i]) && pairedBlocked[i] == aloneBlocked[i] ? 0 : 1;
        hits += paired[i].valid() ? 1 : 0;
      }
      BOOST_TEST(mismatches == 0u, label);
      BOOST_TEST(hits > n / 10, label << ": too few hits to mean anything");
      const bool bvhObjects = cs[s].options.topLevel == TopLevelKind::Bvh &&
                              cs[s].options.staticAccel != AccelKind::SahKdTree;
      if (bvhObjects && kernels.traversePair != nullptr)
        BOOST_TEST(pairedClosest < aloneClosest, label);
      if (bvhObjects && kernels.traversePair == nullptr)
        BOOST_TEST(pairedClosest == aloneClosest, label);
      if (bvhObjects && kernels.occludedPair != nullptr)
        BOOST_TEST(pairedCtx.nodeVisits - pairedClosest < aloneCtx.nodeVisits - aloneClosest,
                   label);
    }
  }
}

BOOST_AUTO_TEST_CASE(flat_packets_equal_single_rays) {
  checkAllKernels(false, 2024);
}

BOOST_AUTO_TEST_CASE(instanced_packets_equal_single_rays) {
  checkAllKernels(true, 77);
}

/// Every field of two object rays, bit for bit (padding aside).
bool sameObjectRay(const ObjectRay& a, const ObjectRay& b) {
  bool same = a.wt.kx == b.wt.kx && a.wt.ky == b.wt.ky && a.wt.kz == b.wt.kz &&
              sameBits(a.wt.tnear, b.wt.tnear) && sameBits(a.wt.sx, b.wt.sx) &&
              sameBits(a.wt.sy, b.wt.sy) && sameBits(a.wt.sz, b.wt.sz) &&
              sameBits(a.tfar, b.tfar) && a.instanceId == b.instanceId && a.objectId == b.objectId;
  for (std::size_t c = 0; c < 3; ++c) {
    same = same && sameBits(a.wt.origin[c], b.wt.origin[c]) &&
           sameBits(a.wt.direction[c], b.wt.direction[c]) &&
           sameBits(a.wt.originD[c], b.wt.originD[c]) &&
           sameBits(a.wt.directionD[c], b.wt.directionD[c]) &&
           sameBits(a.inverseDirection[c], b.inverseDirection[c]);
  }
  return same;
}

/// A packet of rays for trial `trial` of the mapping tests: random origins and directions with
/// zero components of either sign and ties for the largest component among them.
void makeMappingRays(std::mt19937& rng, int trial, Ray (&rays)[kRayPacketSize],
                     float (&tfar)[kRayPacketSize]) {
  std::uniform_real_distribution<float> coord(-50.0f, 50.0f);
  for (unsigned l = 0; l < kRayPacketSize; ++l) {
    const unsigned t = static_cast<unsigned>(trial) + l;
    rays[l].origin = {coord(rng), coord(rng), coord(rng)};
    rays[l].direction = {coord(rng), coord(rng), coord(rng)};
    if (t % 5 == 0) rays[l].direction.x = 0.0f;
    if (t % 7 == 0) rays[l].direction.y = -0.0f;
    // Ties for the largest component, which the axis permutation breaks towards x, then y.
    if (t % 11 == 3) rays[l].direction.z = -rays[l].direction.x;
    if (t % 13 == 4) rays[l].direction.y = rays[l].direction.z;
    if (t % 17 == 5) rays[l].direction = {-2.0f, 2.0f, -2.0f};
    rays[l].tnear = static_cast<float>(l) * 0.25f;
    tfar[l] = 10.0f + static_cast<float>(l);
  }
}

/// The instance of mapping trial `trial`: the identity, or a random transform with mirrors.
InstanceRecord mappingInstance(std::mt19937& rng, int trial, bool identity) {
  InstanceRecord inst;
  inst.identity = identity;
  if (!identity) inst.worldToObjectD = *randomTransform(rng, 20.0, true).inverse();
  inst.instanceId = static_cast<std::uint32_t>(trial);
  inst.objectId = static_cast<std::uint32_t>(trial / 2);
  return inst;
}

/// The lanes of mapping trial `trial`: all of them, or a pseudo-random non-empty subset.
unsigned mappingLanes(int trial) {
  const unsigned all = (1u << kRayPacketSize) - 1u;
  const unsigned lanes = trial % 4 == 0 ? all : (static_cast<unsigned>(trial) * 37u) & all;
  return lanes != 0 ? lanes : 1u;
}

/// One trial of the mapping tests: an instance, a packet of rays with their tfar, the lanes.
struct MappingTrial {
  InstanceRecord inst;
  Ray rays[kRayPacketSize];
  float tfar[kRayPacketSize];
  unsigned lanes = 0;
};

MappingTrial makeMappingTrial(std::mt19937& rng, int trial, bool identity) {
  MappingTrial t;
  t.inst = mappingInstance(rng, trial, identity);
  makeMappingRays(rng, trial, t.rays, t.tfar);
  t.lanes = mappingLanes(trial);
  return t;
}

BOOST_AUTO_TEST_CASE(packet_object_rays_equal_single_mapping) {
  // The packet walk maps its lanes into an instance with vector divisions; each lane must be the
  // object ray the single-ray walk builds, for identity and transformed instances alike, with
  // zero direction components of either sign among them.
  std::mt19937 rng(31);
  for (int trial = 0; trial < 200; ++trial) {
    const MappingTrial setup = makeMappingTrial(rng, trial, trial % 3 == 0);
    const auto& [inst, rays, tfar, lanes] = setup;
    ObjectRayPacket packet;
    detail::mapPacketToObject(inst, rays, lanes, tfar, packet);
    for (unsigned l = 0; l < kRayPacketSize; ++l) {
      if (!(lanes & (1u << l))) continue;
      BOOST_TEST(sameObjectRay(packet.rays[l], objectRayFor(inst, rays[l], tfar[l])),
                 "trial " << trial << " lane " << l);
    }
  }
}

/// Every float (or double) of rows `a` and `b`, bit for bit.
template <class T, std::size_t N>
bool sameRows(const T (&a)[N], const T (&b)[N]) {
  for (std::size_t i = 0; i < N; ++i)
    if (!sameBits(a[i], b[i])) return false;
  return true;
}

/// Every row and the axis permutation of two triangle-test loads, bit for bit.
bool sameTriangleRows(const detail::PacketTriangleRays& t, const detail::PacketTriangleRays& e) {
  bool same = t.kx == e.kx && t.ky == e.ky && t.kz == e.kz;
  for (int a = 0; a < 3; ++a)
    same = same && sameRows(t.origin[a], e.origin[a]) && sameRows(t.originD[a], e.originD[a]) &&
           sameRows(t.directionD[a], e.directionD[a]);
  return same && sameRows(t.sx, e.sx) && sameRows(t.sy, e.sy) && sameRows(t.tnear, e.tnear);
}

/// Runs trial(trial number, instruction set) `perIsa` times for each instruction set this CPU
/// runs, in turn, with that set's kernels active.
template <class Trial>
void forEachIsaTrial(int perIsa, const Trial& trial) {
  IsaGuard guard;
  const std::vector<SimdIsa> isas = supportedSimdIsas();
  for (int k = 0; k < perIsa * static_cast<int>(isas.size()); ++k) {
    const SimdIsa isa = isas[static_cast<std::size_t>(k) % isas.size()];
    BOOST_REQUIRE(setSimdIsa(isa));
    trial(k, isa);
  }
}

BOOST_AUTO_TEST_CASE(transformed_packets_load_as_mapped_object_rays) {
  // The packet walk loads a transformed instance's rows straight from the world rays, with the
  // kernels of each instruction set, and makes a lane's object ray only when a test reads it:
  // rows, lane sets and the rays made later must all be what mapping every lane (objectRayFor)
  // and loading them (loadPacket) give.
  std::mt19937 rng(43);
  forEachIsaTrial(300, [&](int trial, SimdIsa isa) {
    const detail::PacketKernels& kernels = detail::activePacketKernels();
    const MappingTrial setup = makeMappingTrial(rng, trial, false);
    const auto& [inst, rays, tfar, lanes] = setup;

    ObjectRayPacket mapped;
    detail::mapPacketToObject(inst, rays, lanes, tfar, mapped);
    detail::BvhPacketRays expected;
    detail::BvhAccel::loadPacket(mapped, lanes, expected);

    ObjectRayPacket lazy;
    detail::BvhPacketRays loaded;
    detail::loadTransformedPacket(inst, rays, lanes, tfar, kernels, lazy, loaded);
    BOOST_TEST_CONTEXT("trial " << trial << ", " << simdIsaName(isa)) {
      BOOST_TEST(loaded.coherent == expected.coherent);
      BOOST_TEST(loaded.filtered == expected.filtered);
      BOOST_TEST(loaded.unmappedLanes == lanes);
      BOOST_TEST(sameRows(loaded.box.origin[0], expected.box.origin[0]));
      BOOST_TEST(sameRows(loaded.box.origin[1], expected.box.origin[1]));
      BOOST_TEST(sameRows(loaded.box.origin[2], expected.box.origin[2]));
      BOOST_TEST(sameRows(loaded.box.reciprocal[0], expected.box.reciprocal[0]));
      BOOST_TEST(sameRows(loaded.box.reciprocal[1], expected.box.reciprocal[1]));
      BOOST_TEST(sameRows(loaded.box.reciprocal[2], expected.box.reciprocal[2]));
      BOOST_TEST(sameRows(loaded.box.tnear, expected.box.tnear));
      BOOST_TEST(sameRows(loaded.box.tfar, expected.box.tfar));
      BOOST_TEST(loaded.box.signs == expected.box.signs);
      BOOST_TEST(sameTriangleRows(loaded.triangles, expected.triangles));
      for (unsigned m = lanes; m != 0; m &= m - 1) {
        const unsigned l = static_cast<unsigned>(__builtin_ctz(m));
        BOOST_TEST(sameObjectRay(detail::BvhAccel::packetLane(lazy, loaded, l), mapped.rays[l]),
                   "lane " << l);
      }
      BOOST_TEST(loaded.unmappedLanes == 0u);
    }
  });
}

BOOST_AUTO_TEST_CASE(identity_packets_load_as_mapped_object_rays) {
  // A walk entering identity instances loads the triangle rows of its lanes (which share their
  // direction signs) straight from the world rays, with the kernels of each instruction set: rows
  // and lane sets must be what mapping every lane and loading them (loadPacket) give. Every other
  // trial's directions share one octant and dominant axis, which takes the whole-row path.
  std::mt19937 rng(47);
  forEachIsaTrial(300, [&](int trial, SimdIsa isa) {
    MappingTrial setup = makeMappingTrial(rng, trial, true);
    if (trial % 2 == 0)
      for (Ray& r : setup.rays)
        r.direction = {60.0f + std::abs(r.direction.x), std::abs(r.direction.y),
                       -1.0f - std::abs(r.direction.z)};
    ObjectRayPacket mapped;
    detail::mapPacketToObject(setup.inst, setup.rays, setup.lanes, setup.tfar, mapped);
    detail::BvhPacketRays expected;
    detail::BvhAccel::loadPacket(mapped, setup.lanes, expected);
    // The walk's lanes: those whose signs match the first's.
    const unsigned lanes = expected.coherent;

    detail::PacketTriangleRays t;
    const detail::LoadedLanes found =
        detail::activePacketKernels().loadIdentityRows(setup.rays, lanes, t);
    detail::setTrianglePermutation(found, t);
    BOOST_TEST_CONTEXT("trial " << trial << ", " << simdIsaName(isa)) {
      if (trial % 4 == 0) BOOST_TEST(found.filtered == detail::kAllLanes);
      BOOST_TEST(found.coherent == lanes);
      BOOST_TEST(found.filtered == expected.filtered);
      BOOST_TEST(sameTriangleRows(t, expected.triangles));
    }
  });
}

BOOST_AUTO_TEST_CASE(packets_match_reference) {
  IsaGuard guard;
  std::mt19937 rng(5);
  const auto scenes = makeScenes(rng, true);
  const ReferenceIntersector ref(*scenes.front());
  const Box3f box = scenes.front()->bounds();
  const std::vector<Ray> rays = cameraRays(rng, box, 40);
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    std::vector<Hit> hits(rays.size());
    TraversalContext ctx;
    scenes.front()->intersect(std::span<const Ray>(rays), std::span<Hit>(hits), ctx);
    std::size_t checked = 0, mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const ReferenceHit e = ref.intersect(rays[i]);
      if (e.hitAmbiguous) continue;
      ++checked;
      bool ok = hits[i].valid() == e.hit;
      if (ok && e.hit) {
        ok =
            std::abs(double(hits[i].t) - e.t) <=
                8.0 * ReferenceIntersector::tolerance(rays[i], e.t) &&
            (e.primAmbiguous || (hits[i].instanceId == e.instanceId && hits[i].primId == e.primId));
      }
      if (!ok && mismatches++ == 0)
        BOOST_ERROR(simdIsaName(isa) << ": " << describe(rays[i]) << " packet t " << hits[i].t
                                     << " reference t " << e.t);
    }
    BOOST_TEST(checked > rays.size() / 2);
    BOOST_TEST(mismatches == 0u, simdIsaName(isa));
  }
}

BOOST_AUTO_TEST_CASE(packets_do_not_leak_through_closed_meshes) {
  // Rays from inside a closed icosphere aimed exactly at its vertices and edge midpoints,
  // sorted by direction octant so that consecutive rays form coherent packets.
  IsaGuard guard;
  const TriangleMesh mesh = makeIcosphere(4);
  const Vec3f origin{0.01f, -0.02f, 0.03f};
  std::vector<Ray> rays;
  auto shoot = [&](const Vec3f& target) {
    Ray r;
    r.origin = origin;
    r.direction = target - origin;
    rays.push_back(r);
  };
  for (const Vec3f& v : mesh.positions) shoot(v);
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3)
    for (int e = 0; e < 3; ++e)
      shoot((mesh.positions[mesh.indices[i + e]] + mesh.positions[mesh.indices[i + (e + 1) % 3]]) *
            0.5f);
  std::stable_sort(rays.begin(), rays.end(), [](const Ray& a, const Ray& b) {
    auto octant = [](const Vec3f& d) {
      return (d.x < 0.0f ? 1 : 0) | (d.y < 0.0f ? 2 : 0) | (d.z < 0.0f ? 4 : 0);
    };
    return octant(a.direction) < octant(b.direction);
  });
  for (const Config& config : configs()) {
    Scene scene(config.options);
    scene.createInstance(scene.createObject(mesh));
    scene.commit();
    for (SimdIsa isa : supportedSimdIsas()) {
      BOOST_REQUIRE(setSimdIsa(isa));
      std::vector<Hit> hits(rays.size());
      std::vector<std::uint8_t> blocked(rays.size());
      TraversalContext ctx;
      scene.intersect(std::span<const Ray>(rays), std::span<Hit>(hits), ctx);
      scene.occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(blocked), ctx);
      std::size_t leaks = 0, unblocked = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        leaks += hits[i].valid() ? 0 : 1;
        unblocked += blocked[i] ? 0 : 1;
      }
      BOOST_TEST_MESSAGE(config.name << " " << simdIsaName(isa) << ": " << leaks << " leaks in "
                                     << rays.size() << " rays");
      BOOST_TEST(leaks == 0u, config.name << " " << simdIsaName(isa));
      BOOST_TEST(unblocked == 0u, config.name << " " << simdIsaName(isa));
      // Rays through edges and vertices meet edge functions exactly zero, which the SIMD
      // triangle test hands to the scalar one in the middle of a batch: still the same hits.
      const Comparison c = compareWithSingleRays(scene, rays);
      BOOST_TEST(c.mismatches == 0u,
                 config.name << " " << simdIsaName(isa) << ": " << c.firstMismatch);
    }
  }
}

BOOST_AUTO_TEST_CASE(every_untraceable_field_in_every_lane) {
  // The span queries check the eight rays of a packet at once: each kind of bad value, in each
  // float of the ray and at each lane position (and in a short tail), must be rejected exactly
  // as the single-ray query rejects it, without disturbing the other lanes.
  IsaGuard guard;
  std::mt19937 rng(5);
  const auto scenes = makeScenes(rng, false);
  const Scene& scene = *scenes.front();
  const std::vector<Ray> camera = cameraRays(rng, scene.bounds(), 1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> rays;
  for (int field = 0; field < 8; ++field)
    for (const float bad : {nan, -nan, kInfinity, -kInfinity})
      for (std::size_t lane = 0; lane < kRayPacketSize; ++lane) {
        const std::size_t base = rays.size();
        rays.insert(rays.end(), camera.begin(), camera.begin() + kRayPacketSize);
        Ray& r = rays[base + lane];
        if (field < 3) r.origin[static_cast<std::size_t>(field)] = bad;
        if (field == 3) r.tnear = bad;
        if (field >= 4 && field < 7) r.direction[static_cast<std::size_t>(field - 4)] = bad;
        if (field == 7) r.tfar = bad;
      }
  for (std::size_t lane = 0; lane < kRayPacketSize; ++lane) {
    const std::size_t base = rays.size();
    rays.insert(rays.end(), camera.begin(), camera.begin() + kRayPacketSize);
    rays[base + lane].direction = lane % 2 ? Vec3f(-0.0f, 0.0f, -0.0f) : Vec3f(0.0f, 0.0f, 0.0f);
    const std::size_t next = rays.size();
    rays.insert(rays.end(), camera.begin(), camera.begin() + kRayPacketSize);
    // tnear above tfar: rejected; equal: a one-point interval, which is traced (hard case 11).
    rays[next + lane].tnear = lane % 2 ? 2e30f : 1e30f;
    rays[next + lane].tfar = 1e30f;
  }
  rays.resize(rays.size() - 3);
  for (SimdIsa isa : supportedSimdIsas()) {
    BOOST_REQUIRE(setSimdIsa(isa));
    const Comparison c = compareWithSingleRays(scene, rays);
    BOOST_TEST(c.mismatches == 0u, simdIsaName(isa) << ": " << c.firstMismatch);
    BOOST_TEST(c.hits > c.rays / 2, simdIsaName(isa) << ": the good lanes must hit");
  }
}

BOOST_AUTO_TEST_CASE(mismatched_spans_are_rejected) {
  Scene scene;
  scene.createInstance(scene.createObject(makeBox()));
  scene.commit();
  std::vector<Ray> rays(5);
  std::vector<Hit> hits(4);
  std::vector<std::uint8_t> blocked(6);
  TraversalContext ctx;
  BOOST_CHECK_THROW(scene.intersect(std::span<const Ray>(rays), std::span<Hit>(hits), ctx), Error);
  BOOST_CHECK_THROW(
      scene.occluded(std::span<const Ray>(rays), std::span<std::uint8_t>(blocked), ctx), Error);
  // An empty stream is fine.
  scene.intersect(std::span<const Ray>(), std::span<Hit>(), ctx);
  BOOST_TEST(ctx.nodeVisits == 0u);
}
