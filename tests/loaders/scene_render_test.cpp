// Every shared sample scene (BART AFF, NFF, X3D, glTF and the other Assimp formats) loaded as
// the tools load it (loadSceneSource), synced and rendered at the start, middle and end of its
// animation: the camera must see the scene, and an animated scene must look different at
// different times while a static one renders identically.
#define BOOST_TEST_MODULE scene_render
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "tracegraph/backend/render/Renderer.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

namespace fs = std::filesystem;

namespace {

const fs::path kData = TG_DATA_DIR;

/// A sample scene and what its animation should do.
struct Sample {
  fs::path file;
  bool animated = false;  ///< the file animates something the camera sees
};

/// The shared samples this test knows about, skipping those not installed. The animated ones
/// are named: a file whose animation stopped being read would otherwise pass as static.
std::vector<Sample> samples() {
  const std::vector<Sample> all = {
      {kData / "bart/kitchen/aff/kitchen.aff", true},
      {kData / "bart/robots/aff/Robot.aff", true},
      {kData / "bart/museum/aff/museum5.aff", true},
      {kData / "nff/spheres.nff", false},
      {kData / "nff/cone.nff", false},
      {kData / "nff/cylinder.nff", false},
      {kData / "nff/dodecahedron.nff", false},
      {kData / "nff/hexahedron.nff", false},
      {kData / "nff/octahedron.nff", false},
      {kData / "nff/tetrahedron.nff", false},
      {kData / "nff/positionTest.nff", false},
      {kData / "nff/WithCamera.nff", false},
      {kData / "nff/ManyEarthsNotJustOne.nff", false},
      {kData / "x3d/HelloWorld.x3d", false},
      {kData / "x3d/ComputerKeyboard.x3d", true},
      {kData / "gltf/AnimatedTriangle/AnimatedTriangle.gltf", true},
      {kData / "gltf/BoxAnimated/BoxAnimated.gltf", true},
      {kData / "gltf/BoxTextured-glTF/BoxTextured.gltf", false},
      {kData / "gltf/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", false},
      {kData / "gltf/cameras/Cameras.gltf", false},
      {kData / "gltf/SimpleMorph/glTF/SimpleMorph.gltf", true},
      {kData / "gltf/AnimatedMorphCube/glTF/AnimatedMorphCube.gltf", true},
      {kData / "gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf", true},
      {kData / "gltf/simple_skin/simple_skin.gltf", true},
      {kData / "gltf/simple_skin/quad_skin.glb", false},
  };
  std::vector<Sample> present;
  for (const Sample& s : all)
    if (fs::exists(s.file)) present.push_back(s);
  return present;
}

/// Pixels whose primary ray hit something.
std::size_t coveredPixels(const tg::Frame& frame) {
  std::size_t covered = 0;
  for (std::uint32_t y = 0; y < frame.instanceId.height(); ++y)
    for (std::uint32_t x = 0; x < frame.instanceId.width(); ++x)
      if (frame.instanceId.at(x, y) != tg::kInvalidId) ++covered;
  return covered;
}

/// Largest difference of any channel of any pixel.
float largestDifference(const tg::Image& a, const tg::Image& b) {
  float largest = 0.0f;
  for (std::uint32_t y = 0; y < a.height(); ++y)
    for (std::uint32_t x = 0; x < a.width(); ++x)
      for (std::uint32_t c = 0; c < a.channels(); ++c)
        largest = std::max(largest, std::abs(a.at(x, y, c) - b.at(x, y, c)));
  return largest;
}

/// Loads, syncs and renders one sample at three times (see the file comment).
void checkSample(const Sample& sample) {
  const tg::SceneSource source = tg::loadSceneSource(sample.file.string(), 30.0);
  BOOST_TEST_REQUIRE(source.root.get() != nullptr);
  tg::SceneGraph graph;
  graph.setRoot(source.root);
  tg::RenderSettings settings;
  settings.mode = tg::RenderMode::OpenGL;
  tg::SceneRenderer renderer(graph, settings);
  renderer.setLook(source.look);
  renderer.setTextureSearchPath(source.textureFolders);

  const tg::SceneTiming& timing = source.timing;
  BOOST_TEST(timing.frames >= 1);
  BOOST_TEST(timing.end >= timing.start);
  if (sample.animated) BOOST_TEST(timing.end > timing.start);
  // Start, middle and end, plus a time off the middle: a back-and-forth animation (glTF's
  // simple_skin) is in the same pose at all three.
  const double span = timing.end - timing.start;
  const double times[4] = {timing.start, timing.start + 0.5 * span, timing.end,
                           timing.start + 0.37 * span};
  std::vector<tg::Frame> frames(4);
  for (int i = 0; i < 4; ++i) {
    graph.advanceTo(times[i]);
    graph.sync();
    renderer.update();
    renderer.render(renderer.camera(64, 48), frames[i]);
    // The scene's own camera, or the one framing its bounds, sees a good part of it.
    BOOST_TEST(coveredPixels(frames[i]) > 64u * 48u / 50u, "time " << times[i]);
  }
  float largest = 0.0f;
  for (int i = 1; i < 4; ++i)
    largest = std::max(largest, largestDifference(frames[0].beauty, frames[i].beauty));
  if (sample.animated) {
    BOOST_TEST(largest > 0.01f);
  } else {
    BOOST_TEST(largest == 0.0f);
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(every_sample_renders_at_start_middle_and_end) {
  const std::vector<Sample> present = samples();
  if (present.empty())
    BOOST_TEST_MESSAGE("no shared samples under " << kData.string() << " (TG_DATA_DIR)");
  for (const Sample& sample : present) {
    BOOST_TEST_CONTEXT(sample.file.string()) { checkSample(sample); }
  }
}
