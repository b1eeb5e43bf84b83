// TimeSensor and the interpolators, alone and routed into the graph through advanceTo.
#define BOOST_TEST_MODULE interpolators
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../scenegraph/GraphTestUtil.h"
#include "tracegraph/nodes/CoordinateInterpolator.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/ScalarInterpolator.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/scenegraph/Route.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {
constexpr float kPi = 3.14159265f;
}

BOOST_AUTO_TEST_CASE(time_sensor_fraction) {
  auto ts = TimeSensor::create();
  ts->cycleInterval.setValue(2.0);
  ts->startTime.setValue(1.0);
  ts->evaluate(0.5);
  BOOST_TEST(ts->fraction_changed.getValue() == 0.0f);
  ts->evaluate(2.0);
  BOOST_TEST(ts->fraction_changed.getValue() == 0.5f);
  ts->evaluate(10.0);
  BOOST_TEST(ts->fraction_changed.getValue() == 1.0f);  // once: stays at the end
  ts->loop.setValue(true);
  ts->evaluate(4.5);
  BOOST_TEST(ts->fraction_changed.getValue() == 0.75f);
}

BOOST_AUTO_TEST_CASE(position_and_scalar_interpolate_linearly_and_clamp) {
  auto p = PositionInterpolator::create();
  p->key.setValues({0.0f, 0.5f, 1.0f});
  p->keyValue.setValues({{0, 0, 0}, {2, 0, 0}, {2, 4, 0}});
  p->set_fraction.setValue(0.25f);
  p->evaluate(0.0);
  BOOST_TEST(p->value_changed.getValue() == Vec3f(1, 0, 0));
  p->set_fraction.setValue(0.75f);
  p->evaluate(0.0);
  BOOST_TEST(p->value_changed.getValue() == Vec3f(2, 2, 0));
  p->set_fraction.setValue(-1.0f);
  p->evaluate(0.0);
  BOOST_TEST(p->value_changed.getValue() == Vec3f(0, 0, 0));
  p->set_fraction.setValue(3.0f);
  p->evaluate(0.0);
  BOOST_TEST(p->value_changed.getValue() == Vec3f(2, 4, 0));

  auto s = ScalarInterpolator::create();
  s->key.setValues({0.0f, 1.0f});
  s->keyValue.setValues({10.0f, 20.0f});
  s->set_fraction.setValue(0.3f);
  s->evaluate(0.0);
  BOOST_TEST(s->value_changed.getValue() == 13.0f, boost::test_tools::tolerance(1e-6f));
}

BOOST_AUTO_TEST_CASE(orientation_interpolates_spherically) {
  auto o = OrientationInterpolator::create();
  o->key.setValues({0.0f, 1.0f});
  o->keyValue.setValues({Rotation{{0, 1, 0}, 0.0f}, Rotation{{0, 1, 0}, kPi / 2}});
  o->set_fraction.setValue(0.5f);
  o->evaluate(0.0);
  const Rotation r = o->value_changed.getValue();
  BOOST_TEST(r.angle == kPi / 4, boost::test_tools::tolerance(1e-5f));
  BOOST_TEST(r.axis.y == 1.0f, boost::test_tools::tolerance(1e-5f));
}

BOOST_AUTO_TEST_CASE(coordinate_interpolator_blends_point_lists) {
  auto c = CoordinateInterpolator::create();
  c->key.setValues({0.0f, 1.0f});
  c->keyValue.setValues({{0, 0, 0}, {1, 1, 1}, {2, 0, 0}, {1, 3, 1}});
  c->set_fraction.setValue(0.5f);
  c->evaluate(0.0);
  BOOST_TEST(c->value_changed.size() == 2u);
  BOOST_TEST(c->value_changed[0] == Vec3f(1, 0, 0));
  BOOST_TEST(c->value_changed[1] == Vec3f(1, 2, 1));
}

BOOST_AUTO_TEST_CASE(routes_drive_the_graph_through_advance_to) {
  auto ts = TimeSensor::create();
  ts->cycleInterval.setValue(4.0);
  auto pos = PositionInterpolator::create();
  pos->key.setValues({0.0f, 1.0f});
  pos->keyValue.setValues({{0, 0, 0}, {8, 0, 0}});
  auto rot = OrientationInterpolator::create();
  rot->key.setValues({0.0f, 1.0f});
  rot->keyValue.setValues({Rotation{{0, 0, 1}, 0.0f}, Rotation{{0, 0, 1}, kPi}});
  auto t = Transform::create();
  route(*ts, "fraction_changed", *pos, "set_fraction");
  route(*ts, "fraction_changed", *rot, "set_fraction");
  route(*pos, "value_changed", *t, "translation");
  route(*rot, "value_changed", *t, "rotation");
  auto box = makeBox({0.5f, -0.5f, -0.5f}, {1.5f, 0.5f, 0.5f});  // off the rotation axis
  SceneGraph sg;
  sg.setRoot(sep(t, box));
  for (double time : {0.0, 1.0, 2.0, 3.0}) {
    sg.advanceTo(time);
    sg.sync();
    // The time sensor is evaluated before the interpolators it feeds, in the same call.
    const float f = float(time / 4.0);
    BOOST_TEST(t->translation.getValue().x == 8.0f * f, boost::test_tools::tolerance(1e-5f));
    const Vec3d center = t->localMatrix().transformPoint({1, 0, 0});
    const MappedHit h = traceMapped(sg, rayTo(Vec3f(center) + Vec3f(0, 0, 10), Vec3f(center)));
    BOOST_TEST(h.shape == box.get());
    BOOST_TEST(sg.isDynamic(*t));
  }
}
