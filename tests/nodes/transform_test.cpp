// Transform composition (VRML order), MatrixTransform and rotation algebra.
#define BOOST_TEST_MODULE transform
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../scenegraph/GraphTestUtil.h"
#include "tracegraph/nodes/MatrixTransform.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

bool near(const Vec3d& a, const Vec3d& b, double tol = 1e-6) {
  return length(a - b) <= tol;
}

constexpr double kPi = 3.14159265358979323846;

}  // namespace

BOOST_AUTO_TEST_CASE(default_transform_is_identity) {
  BOOST_TEST(Transform::create()->localMatrix() == Affine3d::identity());
}

BOOST_AUTO_TEST_CASE(translation_rotation_scale_apply_scale_first) {
  auto t = Transform::create();
  t->translation.setValue({1, 2, 3});
  t->rotation.setValue(Rotation{{0, 0, 1}, float(kPi / 2)});
  t->scale.setValue({2, 1, 1});
  // (1, 0, 0) -> scale (2, 0, 0) -> rotate 90 deg about z (0, 2, 0) -> translate (1, 4, 3).
  BOOST_TEST(near(t->localMatrix().transformPoint({1, 0, 0}), {1, 4, 3}));
}

BOOST_AUTO_TEST_CASE(center_is_the_pivot_of_rotation_and_scale) {
  auto t = Transform::create();
  t->center.setValue({1, 0, 0});
  t->rotation.setValue(Rotation{{0, 0, 1}, float(kPi)});
  BOOST_TEST(near(t->localMatrix().transformPoint({1, 0, 0}), {1, 0, 0}));  // the pivot stays
  BOOST_TEST(near(t->localMatrix().transformPoint({2, 0, 0}), {0, 0, 0}));
  t->rotation.setValue(Rotation{});
  t->scale.setValue({3, 3, 3});
  BOOST_TEST(near(t->localMatrix().transformPoint({2, 0, 0}), {4, 0, 0}));
}

BOOST_AUTO_TEST_CASE(scale_orientation_rotates_the_scale_axes) {
  auto t = Transform::create();
  t->scale.setValue({2, 1, 1});
  t->scaleOrientation.setValue(Rotation{{0, 0, 1}, float(kPi / 2)});
  // Scaling along the rotated x axis (world y): y doubles, x stays.
  BOOST_TEST(near(t->localMatrix().transformPoint({0, 1, 0}), {0, 2, 0}));
  BOOST_TEST(near(t->localMatrix().transformPoint({1, 0, 0}), {1, 0, 0}));
}

BOOST_AUTO_TEST_CASE(full_composition_matches_the_vrml_formula) {
  auto t = Transform::create();
  const Vec3d T(1, -2, 0.5), C(0.3, 0.2, -0.1), S(1.5, 0.7, 2.0);
  const Rotation R{{1, 2, 3}, 0.7f}, SR{{-1, 0.5f, 0.2f}, 1.1f};
  t->translation.setValue(Vec3f(T));
  t->center.setValue(Vec3f(C));
  t->scale.setValue(Vec3f(S));
  t->rotation.setValue(R);
  t->scaleOrientation.setValue(SR);
  const Affine3d expected =
      Affine3d::translation(T) * Affine3d::translation(Vec3d(Vec3f(C))) * rotationMatrix(R) *
      rotationMatrix(SR) * Affine3d::scaling(Vec3d(Vec3f(S))) *
      rotationMatrix(Rotation{SR.axis, -SR.angle}) * Affine3d::translation(-Vec3d(Vec3f(C)));
  for (const Vec3d& p : {Vec3d(0, 0, 0), Vec3d(1, 2, 3), Vec3d(-4, 0.5, 2)})
    BOOST_TEST(near(t->localMatrix().transformPoint(p), expected.transformPoint(p), 1e-9));
}

BOOST_AUTO_TEST_CASE(matrix_transform_uses_its_matrix) {
  const Affine3d m = Affine3d::translation({1, 2, 3}) * Affine3d::scaling({2, 2, 2});
  auto t = MatrixTransform::create(m);
  BOOST_TEST(t->localMatrix() == m);
  auto box = unitBox();
  SceneGraph sg;
  sg.setRoot(sep(t, box));
  sg.sync();
  BOOST_TEST(traceMapped(sg, rayTo({1, 2, 10}, {1, 2, 3})).t == 6.0f / 7.0f,
             boost::test_tools::tolerance(1e-6f));  // top face at z = 4, direction length 7
}

BOOST_AUTO_TEST_CASE(rotation_algebra) {
  const Rotation r{{0, 2, 0}, 0.5f};
  const Rotation back = toRotation(toQuaternion(r));
  BOOST_TEST(back.angle == 0.5f, boost::test_tools::tolerance(1e-6f));
  BOOST_TEST(back.axis.y == 1.0f, boost::test_tools::tolerance(1e-6f));
  // Halfway between 0 and 90 degrees about z is 45 degrees.
  const Quaternion q = slerp(toQuaternion(Rotation{{0, 0, 1}, 0.0f}),
                             toQuaternion(Rotation{{0, 0, 1}, float(kPi / 2)}), 0.5);
  BOOST_TEST(toRotation(q).angle == float(kPi / 4), boost::test_tools::tolerance(1e-6f));
  // Slerp takes the shorter arc: from +170 to -170 degrees passes through 180.
  const Quaternion a = toQuaternion(Rotation{{0, 0, 1}, float(170 * kPi / 180)});
  const Quaternion b = toQuaternion(Rotation{{0, 0, 1}, float(-170 * kPi / 180)});
  const Vec3d x = rotate(slerp(a, b, 0.5), {1, 0, 0});
  BOOST_TEST(near(x, {-1, 0, 0}));
  BOOST_TEST(rotationMatrix(Rotation{{0, 0, 0}, 1.0f}) == Affine3d::identity());
}

BOOST_AUTO_TEST_CASE(quaternion_from_basis_inverts_the_rotation_matrix) {
  // A small angle (trace > 0) and half turns about x, y and z reach each of Shepperd's four
  // cases; the basis is the matrix's columns, the images of the unit axes.
  const Rotation cases[] = {{{1, 2, 3}, 0.3f},
                            {{1, 0, 0}, float(kPi)},
                            {{0, 1, 0}, float(kPi)},
                            {{0, 0, 1}, float(kPi)},
                            {{1, -1, 0.5f}, 2.5f}};
  for (const Rotation& r : cases) {
    const Quaternion expected = toQuaternion(r);
    const Quaternion q = quaternionFromBasis(
        rotate(expected, {1, 0, 0}), rotate(expected, {0, 1, 0}), rotate(expected, {0, 0, 1}));
    // q and -q are the same rotation.
    const double sign =
        q.w * expected.w + q.x * expected.x + q.y * expected.y + q.z * expected.z < 0.0 ? -1.0
                                                                                        : 1.0;
    BOOST_TEST(sign * q.w == expected.w, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(sign * q.x == expected.x, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(sign * q.y == expected.y, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(sign * q.z == expected.z, boost::test_tools::tolerance(1e-9));
  }
}
