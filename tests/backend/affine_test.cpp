// Affine3::transformBox: the per-term (Arvo) bounds against the box of the eight transformed
// corners, for rotations, negative and non-uniform scales, both precisions, and the empty and
// infinite boxes.
#define BOOST_TEST_MODULE affine
#include <boost/test/unit_test.hpp>

#include <limits>
#include <random>
#include <vector>

#include "tracegraph/backend/Affine.h"

using namespace tg;

namespace {

/// The reference: every corner through transformPoint.
template <typename T>
Box3<T> cornerBox(const Affine3<T>& m, const Box3<T>& b) {
  Box3<T> out;
  for (int i = 0; i < 8; ++i) {
    const Vec3<T> corner{(i & 1) ? b.upper.x : b.lower.x, (i & 2) ? b.upper.y : b.lower.y,
                         (i & 4) ? b.upper.z : b.lower.z};
    out.extend(m.transformPoint(corner));
  }
  return out;
}

template <typename T>
bool sameBox(const Box3<T>& a, const Box3<T>& b) {
  for (int k = 0; k < 3; ++k)
    if (!(a.lower[k] == b.lower[k]) || !(a.upper[k] == b.upper[k])) return false;
  return true;
}

template <typename T>
std::vector<Affine3<T>> sampleTransforms() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<T> u(T(-1), T(1)), angle(T(0), T(360)), scale(T(0.01), T(50));
  std::vector<Affine3<T>> out{Affine3<T>::identity(), Affine3<T>::scaling({T(-1), T(2), T(-0.5)}),
                              Affine3<T>::translation({T(3), T(-4), T(5)}) *
                                  Affine3<T>::rotation({T(0), T(0), T(1)}, T(90))};
  for (int i = 0; i < 500; ++i) {
    const Vec3<T> s{scale(rng) * (u(rng) < 0 ? T(-1) : T(1)), scale(rng),
                    scale(rng) * (u(rng) < 0 ? T(-1) : T(1))};
    out.push_back(Affine3<T>::translation({u(rng) * 100, u(rng) * 100, u(rng) * 100}) *
                  Affine3<T>::rotation({u(rng), u(rng), u(rng)}, angle(rng)) *
                  Affine3<T>::scaling(s));
  }
  return out;
}

template <typename T>
void checkAgainstCorners() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<T> pos(T(-20), T(20)), ext(T(0), T(5));
  for (const Affine3<T>& m : sampleTransforms<T>()) {
    for (int k = 0; k < 4; ++k) {
      const Vec3<T> lo{pos(rng), pos(rng), pos(rng)};
      // k == 0: a point box.
      const Vec3<T> e = k == 0 ? Vec3<T>{} : Vec3<T>{ext(rng), ext(rng), ext(rng)};
      const Box3<T> b{lo, lo + e};
      const Box3<T> got = m.transformBox(b), want = cornerBox(m, b);
      BOOST_TEST(sameBox(got, want));
    }
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(equals_the_corner_box_bit_for_bit) {
  checkAgainstCorners<double>();
  checkAgainstCorners<float>();
}

BOOST_AUTO_TEST_CASE(empty_box_stays_empty) {
  const Affine3d m = Affine3d::translation({1, 2, 3}) * Affine3d::rotation({1, 1, 0}, 30.0);
  BOOST_TEST(m.transformBox(Box3d{}).empty());
  BOOST_TEST(m.transformBox(Box3d{{1, 0, 0}, {0, 1, 1}}).empty());
}

BOOST_AUTO_TEST_CASE(infinite_boxes_map_without_nan) {
  const double inf = std::numeric_limits<double>::infinity();
  // Infinite along x only: a rotation about z spreads it over x and y, z stays as it was; a
  // plain translation or mirror keeps it infinite along x alone.
  const Box3d slab{{-inf, 0, 0}, {inf, 1, 2}};
  const Box3d rotated =
      (Affine3d::translation({5, 6, 7}) * Affine3d::rotation({0, 0, 1}, 30.0)).transformBox(slab);
  BOOST_TEST(rotated.lower.x == -inf);
  BOOST_TEST(rotated.upper.x == inf);
  BOOST_TEST(rotated.lower.y == -inf);
  BOOST_TEST(rotated.upper.y == inf);
  BOOST_TEST(rotated.lower.z == 7.0);
  BOOST_TEST(rotated.upper.z == 9.0);
  const Box3d mirrored =
      (Affine3d::translation({1, 1, 1}) * Affine3d::scaling({-2, 1, -1})).transformBox(slab);
  BOOST_TEST(mirrored.lower.x == -inf);
  BOOST_TEST(mirrored.upper.x == inf);
  BOOST_TEST(mirrored.lower.y == 1.0);
  BOOST_TEST(mirrored.upper.y == 2.0);
  BOOST_TEST(mirrored.lower.z == -1.0);
  BOOST_TEST(mirrored.upper.z == 1.0);
  // Infinite everywhere: stays infinite everywhere under any transform.
  const Box3d all{{-inf, -inf, -inf}, {inf, inf, inf}};
  const Box3d spun = Affine3d::rotation({1, 2, 3}, 77.0).transformBox(all);
  for (int a = 0; a < 3; ++a) {
    BOOST_TEST(spun.lower[a] == -inf);
    BOOST_TEST(spun.upper[a] == inf);
  }
  // Half-infinite: x in [0, inf) mirrored becomes (-inf, 0].
  const Box3d half{{0, 0, 0}, {inf, 1, 1}};
  const Box3d flipped = Affine3d::scaling({-1, 1, 1}).transformBox(half);
  BOOST_TEST(flipped.lower.x == -inf);
  BOOST_TEST(flipped.upper.x == 0.0);
}
