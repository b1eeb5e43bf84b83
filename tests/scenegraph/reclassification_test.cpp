// Reclassification without the application's help: static parts that start moving become
// rigid (or deforming), parts at rest return to static, with hysteresis against ping-pong.
#define BOOST_TEST_MODULE reclassification
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

SyncOptions fastRest() {
  SyncOptions o;
  o.restFrames = 5;
  o.maxRestDoublings = 2;
  return o;
}

/// Class of the (single) instance holding `shape`.
DynamicsClass classOf(const SceneGraph& sg, const ShapeNode& shape) {
  const std::vector<InstanceId> ids = sg.instancesOf(shape);
  BOOST_REQUIRE(ids.size() == 1u);
  return sg.instanceClass(ids[0]);
}

/// The scene still answers like one built from scratch (a ray down the box's axis).
void checkHit(const SceneGraph& sg, const Transform& t, const Mesh& box) {
  const Vec3f c = t.translation.getValue();
  const MappedHit h = traceMapped(sg, rayTo(c + Vec3f(0, 0, 10), c));
  BOOST_TEST(h.hit);
  BOOST_TEST(h.shape == &box);
  BOOST_TEST(h.t == 0.95f, boost::test_tools::tolerance(1e-5f));
}

}  // namespace

BOOST_AUTO_TEST_CASE(static_part_moves_then_rests_with_hysteresis) {
  auto box = unitBox();
  auto t = translate({0, 0, 0});
  auto root = sep(sep(t, box), sep(translate({5, 0, 0}), unitBox()));
  SceneGraph sg(fastRest());
  sg.setRoot(root);
  BOOST_TEST(sg.sync().reclassified == 0u);  // frame 1
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Static);

  // Frame 2: the static part starts moving and becomes rigid.
  t->translation.setValue({1, 0, 0});
  FrameStats s = sg.sync();
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(sg.debugStats().promoted == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Rigid);
  checkHit(sg, *t, *box);

  // Frames 3..6 at rest: still rigid. Frame 7 (5 frames after the last move): static again.
  for (int frame = 3; frame <= 6; ++frame) {
    s = sg.sync();
    BOOST_TEST(s.reclassified == 0u);
    BOOST_TEST(classOf(sg, *box) == DynamicsClass::Rigid);
  }
  s = sg.sync();
  BOOST_TEST(s.frame == 7u);
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(sg.debugStats().demoted == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Static);
  checkHit(sg, *t, *box);

  // Frame 8: moves again. Having been demoted once, it now needs 10 frames of rest.
  t->translation.setValue({2, 0, 0});
  BOOST_TEST(sg.sync().reclassified == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Rigid);
  for (int frame = 9; frame <= 17; ++frame) {
    BOOST_TEST(sg.sync().reclassified == 0u);
    BOOST_TEST(classOf(sg, *box) == DynamicsClass::Rigid);
  }
  s = sg.sync();
  BOOST_TEST(s.frame == 18u);
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Static);
  checkHit(sg, *t, *box);
}

BOOST_AUTO_TEST_CASE(part_moving_every_few_frames_does_not_ping_pong) {
  auto box = unitBox();
  auto t = translate({0, 0, 0});
  auto root = sep(sep(t, box), sep(translate({5, 0, 0}), unitBox()));
  SceneGraph sg(fastRest());
  sg.setRoot(root);
  sg.sync();
  std::size_t reclassified = 0;
  for (int frame = 0; frame < 60; ++frame) {
    if (frame % 4 == 0) t->translation.setValue({0.03f * float(frame), 0, 0});
    reclassified += sg.sync().reclassified;
    checkHit(sg, *t, *box);
  }
  BOOST_TEST(reclassified == 1u);  // promoted once, never demoted
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Rigid);
}

BOOST_AUTO_TEST_CASE(mesh_whose_points_change_becomes_deforming_then_static) {
  auto box = unitBox();
  auto root = sep(sep(box), sep(translate({5, 0, 0}), unitBox()));
  SceneGraph sg(fastRest());
  sg.setRoot(root);
  sg.sync();
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Static);
  box->points.edit([](std::vector<Vec3f>& p) {
    for (Vec3f& v : p) v.z += 1.0f;
  });
  FrameStats s = sg.sync();
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Deforming);
  BOOST_TEST(s.triangles.deforming == 12u);
  // Deforming: each further change rebuilds only its object.
  box->points.edit([](std::vector<Vec3f>& p) {
    for (Vec3f& v : p) v.z += 1.0f;
  });
  s = sg.sync();
  BOOST_TEST(s.reclassified == 0u);
  BOOST_TEST(s.objectsRebuilt + s.objectsRefitted == 1u);
  BOOST_TEST(s.trianglesRebuilt == 12u);
  BOOST_TEST(sg.debugStats().regionsRetraversed == 0u);
  BOOST_TEST(traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).t == 0.75f,
             boost::test_tools::tolerance(1e-6f));
  for (int i = 0; i < 5; ++i) s = sg.sync();
  BOOST_TEST(s.reclassified == 1u);
  BOOST_TEST(classOf(sg, *box) == DynamicsClass::Static);
  BOOST_TEST(traceMapped(sg, rayTo({0, 0, 10}, {0, 0, 0})).t == 0.75f,
             boost::test_tools::tolerance(1e-6f));
}
