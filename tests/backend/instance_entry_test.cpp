// InstanceEntry (TopLevelAccel.h): a world ray entering a sequence of instances, identity ones
// sharing one object ray, answers exactly as intersectInstance/occludedInstance entering each
// instance with a freshly mapped ray.
#define BOOST_TEST_MODULE instance_entry
#include <boost/test/unit_test.hpp>

#include <memory>
#include <random>
#include <vector>

#include "TestGeometry.h"
#include "tracegraph/backend/TopLevelAccel.h"

using namespace tg;
using namespace tg::test;

namespace {

struct Objects {
  std::vector<std::unique_ptr<ObjectAccel>> accels;
  std::vector<InstanceRecord> instances;
};

/// Two objects (one per accelerator kind) entered through identity and transformed instances,
/// in an order that alternates between them, with overlapping geometry so that later instances
/// must beat the closest hit of earlier ones.
Objects makeObjects(std::mt19937& rng, AccelKind kind) {
  Objects o;
  for (int k = 0; k < 2; ++k) {
    o.accels.push_back(createObjectAccel(kind));
    o.accels.back()->build(makeRandomTriangles(rng, 300, -4.0f, 4.0f, 1.5f));
  }
  const bool identity[] = {true, false, true, true, false, true};
  for (std::uint32_t i = 0; i < std::size(identity); ++i) {
    InstanceRecord inst;
    inst.accel = o.accels[i % 2].get();
    inst.identity = identity[i];
    if (!inst.identity) {
      const Affine3d toWorld = randomTransform(rng, 3.0, true);
      inst.worldToObjectD = *toWorld.inverse();
    }
    inst.instanceId = 10 + i;
    inst.objectId = i % 2;
    o.instances.push_back(inst);
  }
  return o;
}

}  // namespace

BOOST_AUTO_TEST_CASE(entries_equal_fresh_mappings_hit_by_hit) {
  std::mt19937 rng(17);
  for (const AccelKind kind : {AccelKind::Bvh, AccelKind::BvhFast, AccelKind::SahKdTree}) {
    const Objects o = makeObjects(rng, kind);
    const std::vector<Ray> rays = makeRays(rng, Box3f{{-6, -6, -6}, {6, 6, 6}}, 3000);
    std::size_t hits = 0, occludedCount = 0;
    for (std::size_t r = 0; r < rays.size(); ++r) {
      Ray ray = rays[r];
      // Some rays with a limited interval, so that tfar and tnear both take part.
      if (r % 3 == 1) {
        ray.tnear = 0.25f;
        ray.tfar = 2.0f;
      }
      InstanceEntry enter(ray);
      Hit viaEntry, viaFresh;
      TraversalContext ctx;
      for (const InstanceRecord& inst : o.instances) {
        const bool a = enter.intersect(inst, viaEntry, ctx);
        const bool b = intersectInstance(inst, ray, viaFresh, ctx);
        BOOST_TEST_REQUIRE(a == b, "ray " << r << " instance " << inst.instanceId);
        BOOST_TEST_REQUIRE(sameHitBits(viaEntry, viaFresh),
                           "ray " << r << " instance " << inst.instanceId);
      }
      hits += viaEntry.valid() ? 1 : 0;
      InstanceEntry shadow(ray);
      for (const InstanceRecord& inst : o.instances) {
        const bool a = shadow.occluded(inst, ctx);
        BOOST_TEST_REQUIRE(a == occludedInstance(inst, ray, ctx),
                           "ray " << r << " instance " << inst.instanceId);
        occludedCount += a ? 1 : 0;
      }
    }
    // The rays must exercise both outcomes for the comparison to mean anything.
    BOOST_TEST(hits > rays.size() / 10);
    BOOST_TEST(hits < rays.size());
    BOOST_TEST(occludedCount > 0u);
  }
}
