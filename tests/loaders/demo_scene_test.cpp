// The built-in demo shows the three dynamics classes: its classification counts and a
// `classes` render that contains all three class colours.
#define BOOST_TEST_MODULE demo_scene
#include <boost/test/unit_test.hpp>

#include <set>
#include <tuple>

#include "tracegraph/loaders/DemoScene.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

using namespace tg;

BOOST_AUTO_TEST_CASE(demo_classifies_static_rigid_and_deforming) {
  const DemoScene demo = makeDemoScene();
  BOOST_TEST(demo.staticTriangles > 0u);
  BOOST_TEST(demo.rigidTriangles == 24u);  // two boxes of the arm
  BOOST_TEST(demo.deformingTriangles == 24u * 24u * 2u);
  SceneGraph graph;
  graph.setRoot(demo.root);
  for (double t : {0.0, 0.5, 1.0, 3.7}) {
    graph.advanceTo(t);
    const FrameStats s = graph.sync();
    BOOST_TEST(s.triangles.statics == demo.staticTriangles);
    BOOST_TEST(s.triangles.rigid == demo.rigidTriangles);
    BOOST_TEST(s.triangles.deforming == demo.deformingTriangles);
    if (t > 0.0) {
      // Only the wave is rebuilt (or refitted) after the first frame; the arm moves by its
      // matrices.
      BOOST_TEST(s.objectsRebuilt + s.objectsRefitted == 1u);
      BOOST_TEST(s.trianglesRebuilt == demo.deformingTriangles);
    }
  }
  BOOST_TEST(graph.camera().has_value());
  BOOST_TEST(graph.lights().size() == 2u);
}

BOOST_AUTO_TEST_CASE(classes_render_shows_three_colours_and_the_camera_moves) {
  const DemoScene demo = makeDemoScene();
  SceneGraph graph;
  graph.setRoot(demo.root);
  RenderSettings settings;
  settings.mode = RenderMode::Classes;
  SceneRenderer renderer(graph, settings);
  renderer.setLook(demo.look);
  std::set<DynamicsClass> seen;
  std::vector<float> firstPixels;
  for (double t : {0.0, 2.0}) {
    graph.advanceTo(t);
    graph.sync();
    renderer.update();
    Frame frame;
    renderer.render(renderer.camera(80, 60), frame);
    std::vector<float> pixels;
    for (std::uint32_t y = 0; y < 60; ++y)
      for (std::uint32_t x = 0; x < 80; ++x) {
        pixels.push_back(frame.beauty.at(x, y, 0));
        const std::uint32_t id = frame.instanceId.at(x, y);
        if (id != kInvalidId) seen.insert(graph.instanceClass(id));
      }
    if (firstPixels.empty())
      firstPixels = pixels;
    else
      BOOST_TEST((pixels != firstPixels), "frames at different times must differ");
  }
  BOOST_TEST(seen.count(DynamicsClass::Static) == 1u);
  BOOST_TEST(seen.count(DynamicsClass::Rigid) == 1u);
  BOOST_TEST(seen.count(DynamicsClass::Deforming) == 1u);
}
