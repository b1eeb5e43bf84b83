#include "BenchSceneLoader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <map>
#include <string_view>
#include <system_error>

#include "SceneGenerators.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

namespace tg::bench {
namespace {

constexpr std::string_view kBuiltinPrefix = "builtin:";
constexpr std::string_view kBuiltinHelp =
    "builtin:sphereflake[:depth], builtin:random:N or an .aff/.nff file";

/// Parses all of `text` as an unsigned integer in [lo, hi].
bool parseCount(std::string_view text, std::size_t lo, std::size_t hi, std::size_t& value) {
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, value);
  return r.ec == std::errc{} && r.ptr == end && value >= lo && value <= hi;
}

BenchScene loadBuiltin(const std::string& path) {
  const std::string_view spec = std::string_view(path).substr(kBuiltinPrefix.size());
  std::size_t number = 0;
  if (spec == "sphereflake") return makeSphereflakeScene(3);
  if (spec.starts_with("sphereflake:")) {
    if (!parseCount(spec.substr(12), 0, 6, number))
      throw Error("scene '" + path + "': sphereflake depth must be an integer in 0..6");
    return makeSphereflakeScene(static_cast<int>(number));
  }
  if (spec.starts_with("random:")) {
    // The upper limit keeps 3 * N vertex indices within 32 bits.
    if (!parseCount(spec.substr(7), 1, 100'000'000, number))
      throw Error("scene '" + path + "': random triangle count must be an integer in 1..1e8");
    return makeRandomTriangleScene(number);
  }
  throw Error("unknown built-in scene '" + path + "'; known: " + std::string(kBuiltinHelp));
}

/// Loads an AFF/NFF file through the scene graph, as an application would: the graph at
/// frame 0, synced, then flattened.
BenchScene loadAffFile(const std::string& path) {
  const AffScene aff = loadAff(path);
  SceneGraph graph;
  graph.setRoot(aff.root);
  graph.advanceTo(aff.frameTime(0));
  graph.sync();
  BenchScene bench = flattenSyncedScene(graph);
  // The size is the suite's to choose.
  if (const std::optional<WorldCamera> c = graph.camera()) bench.camera = cameraParamsOf(*c, 1, 1);
  return bench;
}

}  // namespace

bool isAffPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".aff" || ext == ".nff";
}

BenchScene flattenSyncedScene(const SceneGraph& graph) {
  const Scene& synced = graph.backendScene();
  BenchScene bench;
  // Objects shared by several instances (DEF/USE, an `x` track on several blocks) stay
  // shared, so the implementations under test build each once as the scene graph does.
  std::map<ObjectId, std::uint32_t> meshOf;
  for (const InstanceId id : graph.instanceIds()) {
    const ObjectId object = synced.instanceObject(id);
    auto it = meshOf.find(object);
    if (it == meshOf.end()) {
      it = meshOf.emplace(object, static_cast<std::uint32_t>(bench.meshes.size())).first;
      bench.meshes.push_back(synced.objectMesh(object));
    }
    bench.instances.push_back({it->second, synced.instanceTransform(id)});
  }
  return bench;
}

BenchScene loadBenchScene(const std::string& path) {
  BenchScene scene;
  if (path.starts_with(kBuiltinPrefix)) {
    scene = loadBuiltin(path);
  } else if (isAffPath(path)) {
    scene = loadAffFile(path);
  } else {
    throw Error("cannot load '" + path + "': no loader for this file type; use " +
                std::string(kBuiltinHelp));
  }
  scene.name = path;
  return scene;
}

}  // namespace tg::bench
