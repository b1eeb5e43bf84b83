// World normals of hits on identity instances (static geometry) are mapped without their
// matrix, and single hits in scalars: both must give, bit for bit, what the inverse transpose
// of the exact identity gives, signs of zero components included, for single rays and packets.
#define BOOST_TEST_MODULE hit_normal
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "LeafTest.h"
#include "TestGeometry.h"
#include "tracegraph/backend/Scene.h"

using namespace tg;
using namespace tg::test;

namespace {

/// Triangles in the planes x = c, y = c and z = c with both windings, whose object normals have
/// zero components of either sign, beside random triangles.
TriangleMesh makeAxisAlignedAndRandomTriangles(std::mt19937& rng) {
  TriangleMesh mesh = makeRandomTriangles(rng, 300, -2.0f, 2.0f, 0.6f);
  std::uniform_real_distribution<float> pos(-2.0f, 2.0f), off(-0.8f, 0.8f);
  for (int k = 0; k < 600; ++k) {
    const int axis = k % 3;
    const float plane = pos(rng);
    Vec3f v[3];
    for (Vec3f& p : v) {
      p = {pos(rng), pos(rng), pos(rng)};
      p[axis] = plane;
    }
    v[1] = v[0] + Vec3f{off(rng), off(rng), off(rng)};
    v[2] = v[0] + Vec3f{off(rng), off(rng), off(rng)};
    v[1][axis] = v[2][axis] = plane;
    if (k % 2 == 1) std::swap(v[1], v[2]);
    for (const Vec3f& p : v) {
      mesh.positions.push_back(p);
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size() - 1));
    }
  }
  return mesh;
}

/// The object normal of a hit on `prim` as the leaf test leaves it (LeafTest.h).
Vec3f objectNormal(const TriangleMesh& mesh, std::uint32_t prim) {
  const Vec3d a(mesh.positions[mesh.indices[3 * prim]]);
  const Vec3d b(mesh.positions[mesh.indices[3 * prim + 1]]);
  const Vec3d c(mesh.positions[mesh.indices[3 * prim + 2]]);
  return detail::objectNormalForHit(cross(b - a, c - a));
}

/// `object` through the exact identity's inverse transpose, normalised in double.
Vec3f worldNormalOfIdentity(const Vec3f& object) {
  return Vec3f(normalize(Affine3d::identity().transformTransposed(Vec3d(object))));
}

bool sameVectorBits(const Vec3f& a, const Vec3f& b) {
  return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}

bool hasNegativeZero(const Vec3f& v) {
  for (int i = 0; i < 3; ++i)
    if (v[i] == 0.0f && std::signbit(v[i])) return true;
  return false;
}

}  // namespace

BOOST_AUTO_TEST_CASE(identity_instances_map_normals_as_the_exact_identity_does) {
  std::mt19937 rng(11);
  const TriangleMesh mesh = makeAxisAlignedAndRandomTriangles(rng);
  Scene scene;
  const ObjectId object = scene.createObject(mesh);
  // An identity given with -0 entries equals the identity; its hits map as the exact one's.
  Affine3d negativeZeros = Affine3d::identity();
  negativeZeros.m[0][1] = negativeZeros.m[1][2] = negativeZeros.m[2][0] = -0.0;
  scene.createInstance(object, negativeZeros);
  scene.commit();

  const std::vector<Ray> rays = makeRays(rng, Box3f({-2, -2, -2}, {2, 2, 2}), 4000);
  std::vector<Hit> packetHits(rays.size());
  TraversalContext ctx;
  scene.intersect(rays, packetHits, ctx);

  // Object normals with a -0 component: the matrix's sums turn it into +0 unless every
  // component is negative, which mapping without the matrix must reproduce.
  std::size_t hits = 0, negativeZeroNormals = 0, mismatches = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    const bool found = scene.intersect(rays[i], single);
    BOOST_TEST_REQUIRE(found == packetHits[i].valid());
    if (!found) continue;
    ++hits;
    const Vec3f objectSpace = objectNormal(mesh, single.primId);
    const Vec3f expected = worldNormalOfIdentity(objectSpace);
    negativeZeroNormals += hasNegativeZero(objectSpace) ? 1 : 0;
    if (!sameVectorBits(single.geometricNormal, expected) ||
        !sameVectorBits(packetHits[i].geometricNormal, expected)) {
      if (++mismatches <= 5)
        BOOST_ERROR("ray " << describe(rays[i]) << " prim " << single.primId << ": normal ("
                           << single.geometricNormal.x << ", " << single.geometricNormal.y << ", "
                           << single.geometricNormal.z << ") expected (" << expected.x << ", "
                           << expected.y << ", " << expected.z << ")");
    }
  }
  BOOST_TEST(mismatches == 0u);
  // The rays must reach enough of both kinds of triangles for the test to mean something.
  BOOST_TEST(hits > 1000u);
  BOOST_TEST(negativeZeroNormals > 50u);
}
