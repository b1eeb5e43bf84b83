// Lights and the camera found in the graph, evaluated in world space.
#define BOOST_TEST_MODULE lights_camera
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../scenegraph/GraphTestUtil.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/DirectionalLight.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/SpotLight.h"
#include "tracegraph/nodes/Switch.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {
constexpr float kPi = 3.14159265f;
bool near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
  return length(a - b) <= tol;
}
}  // namespace

BOOST_AUTO_TEST_CASE(lights_are_placed_by_their_current_matrix) {
  auto point = PointLight::create();
  point->location.setValue({0, 0, 1});
  auto sun = DirectionalLight::create();
  sun->direction.setValue({0, 0, -1});
  auto spot = SpotLight::create();
  spot->cutOffAngle.setValue(0.3f);
  auto turn = Transform::create();
  turn->rotation.setValue(Rotation{{1, 0, 0}, kPi / 2});  // -z becomes +y
  auto hidden = Switch::create();
  hidden->addChild(PointLight::create());
  auto root = sep(sep(translate({5, 0, 0}), point), sep(turn, sun, translate({0, 0, 2}), spot),
                  hidden, unitBox());
  SceneGraph sg;
  sg.setRoot(root);
  sg.sync();
  const std::vector<WorldLight> lights = sg.lights();
  BOOST_REQUIRE(lights.size() == 3u);  // the switched-off one is not traversed
  BOOST_TEST(lights[0].node == point.get());
  BOOST_TEST((lights[0].data.kind == LightKind::Point));
  BOOST_TEST(near(lights[0].data.position, {5, 0, 1}));
  BOOST_TEST(lights[1].node == sun.get());
  BOOST_TEST(near(lights[1].data.direction, {0, 1, 0}));
  BOOST_TEST((lights[2].data.kind == LightKind::Spot));
  BOOST_TEST(near(lights[2].data.position, {0, -3, 0}));  // (0, 0, 1 + 2) turned about x
  BOOST_TEST(lights[2].data.cutOffAngle == 0.3f);

  // Moving the transform above a light moves it at the next sync.
  turn->rotation.setValue(Rotation{});
  sg.sync();
  BOOST_TEST(near(sg.lights()[1].data.direction, {0, 0, -1}));
  point->intensity.setValue(0.5f);
  sg.sync();
  BOOST_TEST(sg.lights()[0].data.intensity == 0.5f);
  BOOST_TEST(sg.debugStats().regionsRetraversed == 0u);
}

BOOST_AUTO_TEST_CASE(camera_in_world_space) {
  auto cam = Camera::create();
  cam->lookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0});
  BOOST_TEST(near(cam->position.getValue(), {0, 0, 10}));
  auto root = sep(translate({1, 2, 3}), cam, unitBox());
  SceneGraph sg;
  BOOST_TEST(!sg.camera().has_value());
  sg.setRoot(root);
  sg.sync();
  std::optional<WorldCamera> w = sg.camera();
  BOOST_REQUIRE(w.has_value());
  BOOST_TEST(w->node == cam.get());
  BOOST_TEST(near(w->position, {1, 2, 13}));
  BOOST_TEST(near(w->direction, {0, 0, -1}));
  BOOST_TEST(near(w->up, {0, 1, 0}));

  cam->lookAt({10, 0, 0}, {0, 0, 0}, {0, 0, 1});
  sg.sync();
  w = sg.camera();
  BOOST_TEST(near(w->direction, {-1, 0, 0}));
  BOOST_TEST(near(w->up, {0, 0, 1}));
  BOOST_TEST(w->fov == cam->fov.getValue());
}

BOOST_AUTO_TEST_CASE(first_camera_in_traversal_order_wins) {
  auto first = Camera::create(), second = Camera::create();
  SceneGraph sg;
  sg.setRoot(sep(sep(first), second));
  sg.sync();
  BOOST_TEST(sg.camera()->node == first.get());
}
