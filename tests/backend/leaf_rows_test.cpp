// The SIMD leaf test of single rays on its own: a leaf's rows give back its triangles, and the
// four-wide inside step followed by finishWatertight (or by the scalar test for lanes with an
// edge function exactly zero) answers exactly as intersectWatertight does, bit for bit, for
// leaves of one to four triangles, every axis permutation, rays through shared edges and
// vertices (where edge functions are zero) and rays that miss.
#define BOOST_TEST_MODULE leaf_rows
#include <boost/test/unit_test.hpp>

#include <array>
#include <bit>
#include <random>
#include <vector>

#include "LeafRows.h"
#include "LeafTest.h"

using namespace tg;
using namespace tg::detail;

namespace {

/// What a triangle test answers, compared bit for bit.
struct Answer {
  bool hit = false;
  float t = 0.0f, u = 0.0f, v = 0.0f;
  bool operator==(const Answer& o) const {
    if (hit != o.hit) return false;
    if (!hit) return true;
    return std::bit_cast<std::uint32_t>(t) == std::bit_cast<std::uint32_t>(o.t) &&
           std::bit_cast<std::uint32_t>(u) == std::bit_cast<std::uint32_t>(o.u) &&
           std::bit_cast<std::uint32_t>(v) == std::bit_cast<std::uint32_t>(o.v);
  }
};

Answer scalarAnswer(const WatertightRay& ray, const TriangleVertices& tri, float tfar) {
  TriangleHit th;
  Answer a;
  a.hit = intersectWatertight(ray, tri.v0, tri.v1, tri.v2, tfar, th);
  if (a.hit) a = {true, th.t, th.u, th.v};
  return a;
}

#if TG_BVH4_SSE
/// The answers of the SIMD step (forEachLeafRowsHit) for every triangle of a leaf, and the
/// lanes it sent to the scalar test.
std::vector<Answer> simdAnswers(const WatertightRay& ray, const std::vector<float>& rows,
                                std::uint32_t count, float tfar, unsigned& exactLanes) {
  std::vector<Answer> out(count);
  exactLanes = 0;
  withFixedAxes(ray, [&](const auto& axes) {
    LeafInside4 inside;
    insideTest4(ray, axes, rows.data(), count, (1u << count) - 1u, inside);
    exactLanes = inside.exact;
    // The leaf step as BvhAccel runs it, tfar fixed (no hit shortens it here).
    forEachLeafRowsHit(ray, axes, rows.data(), count, tfar,
                       [&](unsigned lane, const TriangleHit& th) {
                         out[lane] = {true, th.t, th.u, th.v};
                         return false;
                       });
    return 0;
  });
  return out;
}
#endif

/// Rows of `tris` with the padding a leaf array carries after its last leaf.
std::vector<float> rowsOf(const std::vector<TriangleVertices>& tris) {
  std::vector<float> rows(9 * tris.size() + kLeafRowPadding, 0.0f);
  writeLeafRows(tris.data(), static_cast<std::uint32_t>(tris.size()), rows.data());
  return rows;
}

}  // namespace

BOOST_AUTO_TEST_CASE(rows_give_back_the_triangles) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coord(-3.0f, 3.0f);
  for (std::uint32_t count = 1; count <= kMaxLeafRowsTriangles; ++count) {
    std::vector<TriangleVertices> tris(count);
    for (TriangleVertices& t : tris)
      t = {{coord(rng), coord(rng), coord(rng)},
           {coord(rng), coord(rng), coord(rng)},
           {coord(rng), coord(rng), coord(rng)}};
    const std::vector<float> rows = rowsOf(tris);
    for (std::uint32_t l = 0; l < count; ++l) {
      const TriangleVertices back = readLeafRows(rows.data(), count, l);
      BOOST_TEST((back.v0 == tris[l].v0 && back.v1 == tris[l].v1 && back.v2 == tris[l].v2),
                 "count " << count << " lane " << l);
    }
  }
}

#if TG_BVH4_SSE
BOOST_AUTO_TEST_CASE(simd_step_answers_as_the_scalar_test) {
  // A fan of triangles around the origin of the xy plane (and tilted copies), hit by rays
  // aimed at random points, at the fan's shared edges and at its centre vertex, from every
  // octant, so that all six axis permutations and exact-zero edge functions occur.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::size_t compared = 0, exactSeen = 0, hitsSeen = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const auto count = static_cast<std::uint32_t>(1 + trial % 4);
    const float tilt = unit(rng);
    std::vector<TriangleVertices> tris(count);
    for (std::uint32_t i = 0; i < count; ++i) {
      const float a0 = 1.5707964f * static_cast<float>(i), a1 = a0 + 1.5707964f;
      const Vec3f centre(0.0f, 0.0f, 0.0f);
      const Vec3f p(std::cos(a0), std::sin(a0), tilt * std::cos(a0));
      const Vec3f q(std::cos(a1), std::sin(a1), tilt * std::cos(a1));
      tris[i] = {centre, p, q};
    }
    const std::vector<float> rows = rowsOf(tris);
    // Target: a random point, a point on a shared edge, or the shared vertex.
    Vec3f target(unit(rng), unit(rng), 0.0f);
    if (trial % 3 == 1) {
      const float s = 0.5f * (unit(rng) + 1.0f);
      target = tris[0].v1 * s;
    } else if (trial % 3 == 2) {
      target = Vec3f(0.0f, 0.0f, 0.0f);
    }
    Vec3f dir(unit(rng), unit(rng), unit(rng));
    if (trial % 5 == 0) dir = Vec3f(0.0f, 0.0f, unit(rng) < 0.0f ? -1.0f : 1.0f);
    if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) dir.z = 1.0f;
    const Vec3f origin = target - dir * 4.0f;
    const WatertightRay ray(origin, dir, 0.0f);
    const float tfar = trial % 7 == 0 ? 3.9f : kInfinity;
    unsigned exact = 0;
    const std::vector<Answer> simd = simdAnswers(ray, rows, count, tfar, exact);
    exactSeen += static_cast<std::size_t>(std::popcount(exact));
    for (std::uint32_t l = 0; l < count; ++l) {
      const Answer scalar = scalarAnswer(ray, tris[l], tfar);
      hitsSeen += scalar.hit ? 1u : 0u;
      BOOST_TEST((simd[l] == scalar), "trial " << trial << " lane " << l);
      ++compared;
    }
  }
  // The cases the test is for did occur.
  BOOST_TEST(compared > 7000u);
  BOOST_TEST(exactSeen > 1000u);
  BOOST_TEST(hitsSeen > 1000u);
}
#endif
