// The closed-interval rule (hard case 11) checked on a one-triangle scene, shared by the hard
// cases and the BVH tests. Include after defining BOOST_TEST_MODULE.
#pragma once

#include <boost/test/unit_test.hpp>

#include <cmath>

#include "tracegraph/backend/Scene.h"

namespace tg::test {

/// The triangle (-1, -1, 5), (1, -1, 5), (0, 1, 5), facing the z axis.
inline TriangleMesh intervalTriangle() {
  TriangleMesh tri;
  tri.positions = {{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}};
  tri.indices = {0, 1, 2};
  return tri;
}

/// Checks that a hit exactly at tnear or tfar counts and one ulp outside does not, on a scene
/// holding intervalTriangle() untransformed.
inline void checkInclusiveIntervalEnds(const Scene& scene) {
  Hit hit;
  // Origin on the triangle, tnear = 0: hit at t = 0.
  BOOST_TEST(scene.intersect({{0, 0, 5}, 0.0f, {0, 0, 1}, kInfinity}, hit));
  BOOST_TEST(hit.t == 0.0f);
  // tfar exactly at the hit: hit; one ulp short: miss.
  BOOST_TEST(scene.intersect({{0, 0, 0}, 0.0f, {0, 0, 1}, 5.0f}, hit));
  BOOST_TEST(hit.t == 5.0f);
  BOOST_TEST(!scene.intersect({{0, 0, 0}, 0.0f, {0, 0, 1}, std::nextafter(5.0f, 0.0f)}, hit));
  BOOST_TEST(scene.occluded({{0, 0, 0}, 0.0f, {0, 0, 1}, 5.0f}));
  BOOST_TEST(!scene.occluded({{0, 0, 0}, 0.0f, {0, 0, 1}, std::nextafter(5.0f, 0.0f)}));
  // tnear exactly at the hit: hit; one ulp beyond: miss.
  BOOST_TEST(scene.intersect({{0, 0, 0}, 5.0f, {0, 0, 1}, kInfinity}, hit));
  BOOST_TEST(!scene.intersect({{0, 0, 0}, std::nextafter(5.0f, 6.0f), {0, 0, 1}, kInfinity}, hit));
  // Origin at the border of the (flat) box, looking along it.
  BOOST_TEST(scene.intersect({{-1, -1, 0}, 0.0f, {0, 0, 1}, kInfinity}, hit));
}

}  // namespace tg::test
