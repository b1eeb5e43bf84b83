// Fields: notifications that say what changed, validation, connections, and edits rejected
// while the graph renders.
#define BOOST_TEST_MODULE fields
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/ScalarInterpolator.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/scenegraph/Route.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

/// Records every notification it hears.
struct Recorder : NodeObserver {
  std::vector<Notification> heard;
  void nodeChanged(const Notification& n) override { heard.push_back(n); }
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(notifications_say_what_changed) {
  auto t = Transform::create();
  auto mesh = unitBox();
  auto mat = Material::create();
  auto sw = Switch::create();
  auto inner = sep(t, mesh, mat, sw);
  auto root = sep(inner);
  Recorder r;
  root->addObserver(&r);

  t->translation.setValue({1, 2, 3});
  BOOST_REQUIRE(r.heard.size() == 1u);
  BOOST_TEST(r.heard[0].source == t.get());
  BOOST_TEST(r.heard[0].kind == ChangeKind::Transform);
  BOOST_TEST(r.heard[0].field == &t->translation);

  t->translation.setValue({1, 2, 3});  // same value: nothing to say
  BOOST_TEST(r.heard.size() == 1u);

  mesh->points.set1Value(0, {0, 0, 0});
  mesh->indices.setValues({0, 1, 2});
  mesh->texCoords.setValues({});  // unchanged (already empty)
  mat->diffuseColor.setValue({1, 0, 0});
  sw->whichChild.setValue(Switch::kAll);
  auto extra = unitBox();
  inner->addChild(extra);
  BOOST_REQUIRE(r.heard.size() == 6u);
  BOOST_TEST(r.heard[1].kind == ChangeKind::Points);
  BOOST_TEST(r.heard[2].kind == ChangeKind::Topology);
  BOOST_TEST(r.heard[3].kind == ChangeKind::Material);
  BOOST_TEST(r.heard[4].kind == ChangeKind::Visibility);
  BOOST_TEST(r.heard[5].kind == ChangeKind::Structure);
  BOOST_TEST(r.heard[5].source == inner.get());
  BOOST_TEST(r.heard[5].child == extra.get());
  BOOST_TEST(toString(ChangeKind::Transform | ChangeKind::Points) == "Transform|Points");
  root->removeObserver(&r);
}

BOOST_AUTO_TEST_CASE(shared_node_notifies_each_ancestor_once) {
  auto t = Transform::create();
  auto shared = sep(t);
  auto root = sep(sep(shared), sep(shared), shared);
  Recorder atRoot, atShared;
  root->addObserver(&atRoot);
  shared->addObserver(&atShared);
  t->scale.setValue({2, 2, 2});
  BOOST_TEST(atRoot.heard.size() == 1u);  // three paths up, one notification
  BOOST_TEST(atShared.heard.size() == 1u);
  root->removeObserver(&atRoot);
  shared->removeObserver(&atShared);
}

BOOST_AUTO_TEST_CASE(invalid_values_are_rejected_and_leave_the_field_unchanged) {
  auto t = Transform::create();
  t->translation.setValue({1, 1, 1});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  BOOST_CHECK_THROW(t->translation.setValue({nan, 0, 0}), Error);
  BOOST_TEST(t->translation.getValue() == Vec3f(1, 1, 1));
  auto mesh = unitBox();
  const std::vector<Vec3f> before = mesh->points.getValues();
  try {
    mesh->points.edit([nan](std::vector<Vec3f>& p) { p[3].y = nan; });
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "points::edit"));
  }
  BOOST_TEST(mesh->points.getValues() == before);
  BOOST_TEST(t->field("translation") == &t->translation);
  BOOST_TEST(t->field("nope") == nullptr);
  BOOST_TEST(t->translation.typeName() == "SFVec3f");
  BOOST_TEST(mesh->indices.typeName() == "MFInt32");
}

BOOST_AUTO_TEST_CASE(connections_check_source_type_and_cycles) {
  auto t = Transform::create();
  auto other = Transform::create();
  auto interp = PositionInterpolator::create();
  auto scalar = ScalarInterpolator::create();
  Recorder r;
  t->addObserver(&r);

  try {
    t->translation.connectFrom(other->translation);
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "Field::connectFrom"));
    BOOST_TEST(contains(e.what(), "not belong to an animator"));
  }
  BOOST_CHECK_THROW(t->translation.connectFrom(scalar->value_changed), Error);  // SFFloat
  BOOST_TEST(!t->translation.isConnected());

  t->translation.connectFrom(interp->value_changed);
  BOOST_TEST(t->translation.isConnected());
  BOOST_TEST(t->isDriven(ChangeKind::Transform));
  BOOST_REQUIRE(r.heard.size() == 1u);
  BOOST_TEST(r.heard[0].kind == ChangeKind::Connection);

  // interp.set_fraction <- scalar.value_changed, scalar.set_fraction <- interp: a cycle.
  interp->set_fraction.connectFrom(scalar->value_changed);
  try {
    scalar->set_fraction.connectFrom(interp->set_fraction);
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "cycle"));
  }
  BOOST_TEST(!scalar->set_fraction.isConnected());

  t->translation.disconnect();
  BOOST_TEST(!t->isDriven(ChangeKind::Transform));
  t->removeObserver(&r);
}

BOOST_AUTO_TEST_CASE(route_by_names) {
  auto clock = TimeSensor::create();
  auto interp = PositionInterpolator::create();
  auto t = Transform::create();
  route(*clock, "fraction_changed", *interp, "set_fraction");
  route(*interp, "value_changed", *t, "translation");
  BOOST_TEST(t->translation.connectedFrom() == &interp->value_changed);
  try {
    route(*interp, "value_changed", *t, "translaton");
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "route"));
    BOOST_TEST(contains(e.what(), "translaton"));
  }
}

BOOST_AUTO_TEST_CASE(edits_are_rejected_while_rendering) {
  auto t = translate({0, 0, 0});
  auto box = unitBox();
  auto root = sep(t, box);
  auto outside = Transform::create();  // not under the root
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  {
    RenderingScope rendering(sg);
    BOOST_TEST(sg.rendering());
    try {
      t->translation.setValue({1, 0, 0});
      BOOST_FAIL("expected tg::Error");
    } catch (const Error& e) {
      BOOST_TEST(contains(e.what(), "translation::setValue"));
      BOOST_TEST(contains(e.what(), "rendered"));
    }
    BOOST_TEST(t->translation.getValue() == Vec3f(0, 0, 0));
    BOOST_CHECK_THROW(root->addChild(unitBox()), Error);
    BOOST_TEST(root->numChildren() == 2u);
    BOOST_CHECK_THROW(sg.sync(), Error);
    BOOST_CHECK_THROW(sg.advanceTo(1.0), Error);
    outside->translation.setValue({1, 0, 0});  // not part of the frame: allowed
  }
  BOOST_TEST(!sg.rendering());
  t->translation.setValue({1, 0, 0});
  sg.sync();
  BOOST_TEST(traceMapped(sg, rayTo({1, 0, 10}, {1, 0, 0})).shape == box.get());
}
