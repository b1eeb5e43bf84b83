// Separator isolates transform and material state; Group does not; Switch selects children.
#define BOOST_TEST_MODULE separator
#include <boost/test/unit_test.hpp>

#include "../scenegraph/GraphTestUtil.h"
#include "tracegraph/nodes/Switch.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

BOOST_AUTO_TEST_CASE(separator_isolates_transform_and_material) {
  auto red = Material::create();
  auto box = unitBox();
  auto root = sep(sep(translate({5, 0, 0}), red), box);
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  const MappedHit atOrigin = traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0}));
  BOOST_TEST(atOrigin.shape == box.get());
  BOOST_TEST(atOrigin.material == nullptr);  // the default material: red stayed inside
  BOOST_TEST(!traceMapped(sg, rayTo({5, 0, 10}, {5, 0, 0})).hit);
}

BOOST_AUTO_TEST_CASE(group_does_not_isolate) {
  auto red = Material::create();
  auto box = unitBox();
  auto inner = Group::create();
  inner->addChild(translate({5, 0, 0}));
  inner->addChild(red);
  auto root = sep(inner, box);
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  BOOST_TEST(!traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).hit);
  const MappedHit moved = traceMapped(sg, rayTo({5, 0, 10}, {5, 0, 0}));
  BOOST_TEST(moved.shape == box.get());
  BOOST_TEST(moved.material == red.get());  // Group leaked both transform and material
}

BOOST_AUTO_TEST_CASE(nested_state_composes_and_restores) {
  auto red = Material::create(), blue = Material::create();
  auto a = unitBox(), b = unitBox(), c = unitBox();
  // translate 2, red, [translate 2 (total 4), blue, b], a at 2 red, then c at 2 red.
  auto root = sep(translate({2, 0, 0}), red, sep(translate({2, 0, 0}), blue, b), a,
                  translate({0, 3, 0}), c);
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  const MappedHit hb = traceMapped(sg, rayTo({4, 0, 10}, {4, 0, 0}));
  const MappedHit ha = traceMapped(sg, rayTo({2, 0, 10}, {2, 0, 0}));
  const MappedHit hc = traceMapped(sg, rayTo({2, 3, 10}, {2, 3, 0}));
  BOOST_TEST(hb.shape == b.get());
  BOOST_TEST(hb.material == blue.get());
  BOOST_TEST(ha.shape == a.get());
  BOOST_TEST(ha.material == red.get());
  BOOST_TEST(hc.shape == c.get());
  BOOST_TEST(hc.material == red.get());
}

BOOST_AUTO_TEST_CASE(switch_traverses_the_chosen_child) {
  auto a = unitBox(), b = makeBox({2.5f, -0.5f, -0.5f}, {3.5f, 0.5f, 0.5f});
  auto sw = Switch::create();
  sw->addChild(a);
  sw->addChild(b);
  SceneGraph sg;
  sg.setRoot(sep(sw));
  sg.sync();
  const Ray toA = rayTo({0, 0, 10}, {0, 0, 0}), toB = rayTo({3, 0, 10}, {3, 0, 0});
  BOOST_TEST(!traceMapped(sg, toA).hit);  // kNone by default
  BOOST_TEST(!traceMapped(sg, toB).hit);
  sw->whichChild.setValue(1);
  sg.sync();
  BOOST_TEST(!traceMapped(sg, toA).hit);
  BOOST_TEST(traceMapped(sg, toB).shape == b.get());
  sw->whichChild.setValue(Switch::kAll);
  sg.sync();
  BOOST_TEST(traceMapped(sg, toA).shape == a.get());
  BOOST_TEST(traceMapped(sg, toB).shape == b.get());
  sw->whichChild.setValue(7);  // out of range: nothing
  sg.sync();
  BOOST_TEST(!traceMapped(sg, toA).hit);
  BOOST_TEST(sg.backendScene().instanceCount() == 0u);
}
