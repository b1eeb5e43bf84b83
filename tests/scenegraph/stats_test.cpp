// Per-frame statistics and their JSON form.
#define BOOST_TEST_MODULE stats
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"
#include "tracegraph/nodes/PositionInterpolator.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

BOOST_AUTO_TEST_CASE(json_has_exactly_the_documented_keys) {
  FrameStats s;
  s.frame = 7;
  s.time = 0.25;
  s.triangles = {100, 20, 3};
  s.instances = 4;
  s.objectsRebuilt = 1;
  s.trianglesRebuilt = 3;
  s.objectsRefitted = 5;
  s.reclassified = 2;
  s.syncMs = 1.5;
  s.rebuildMs = 0.5;
  s.toplevelMs = 0.125;
  s.renderMs = 10;
  s.rays = {1000, 2000, 300, 45};
  BOOST_TEST(toJson(s) ==
             "{\"frame\":7,\"time\":0.25,\"triangles\":{\"static\":100,\"rigid\":20,"
             "\"deforming\":3},\"instances\":4,\"objects_rebuilt\":1,\"triangles_rebuilt\":3,"
             "\"reclassified\":2,\"sync_ms\":1.5,\"rebuild_ms\":0.5,\"toplevel_ms\":0.125,"
             "\"render_ms\":10,\"rays\":{\"primary\":1000,\"shadow\":2000,\"reflection\":300,"
             "\"refraction\":45,\"total\":3345},\"objects_refitted\":5}");
}

BOOST_AUTO_TEST_CASE(sync_fills_the_frame_statistics) {
  auto moving = Transform::create();
  auto interp = PositionInterpolator::create();
  interp->key.setValues({0.0f, 1.0f});
  interp->keyValue.setValues({{0, 0, 0}, {1, 0, 0}});
  moving->translation.connectFrom(interp->value_changed);
  auto shared = sep(unitBox());
  auto root = sep(sep(translate({3, 0, 0}), shared), sep(translate({6, 0, 0}), shared),
                  sep(moving, unitBox()), sep(translate({0, 4, 0}), unitBox()));
  SceneGraph sg;
  sg.setRoot(root);
  sg.advanceTo(0.5);
  FrameStats s = sg.sync();
  BOOST_TEST(s.frame == 1u);
  BOOST_TEST(s.time == 0.5);
  BOOST_TEST(s.triangles.statics == 36u);  // two shared instances + one chunk
  BOOST_TEST(s.triangles.rigid == 12u);
  BOOST_TEST(s.triangles.deforming == 0u);
  BOOST_TEST(s.instances == 4u);
  BOOST_TEST(s.objectsRebuilt == 3u);
  BOOST_TEST(s.trianglesRebuilt == 36u);
  BOOST_TEST(s.syncMs >= s.rebuildMs + s.toplevelMs);
  interp->set_fraction.setValue(0.5f);
  sg.advanceTo(1.0);
  s = sg.sync();
  BOOST_TEST(s.frame == 2u);
  BOOST_TEST(s.objectsRebuilt == 0u);
  BOOST_TEST(s.trianglesRebuilt == 0u);
}
