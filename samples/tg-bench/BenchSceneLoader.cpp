#include "BenchSceneLoader.h"

#include <charconv>
#include <string_view>
#include <system_error>

#include "SceneGenerators.h"
#include "tracegraph/backend/Error.h"

namespace tg::bench {
namespace {

constexpr std::string_view kBuiltinPrefix = "builtin:";
constexpr std::string_view kBuiltinHelp = "builtin:sphereflake[:depth] or builtin:random:N";

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

}  // namespace

BenchScene loadBenchScene(const std::string& path) {
  BenchScene scene;
  if (path.starts_with(kBuiltinPrefix)) {
    scene = loadBuiltin(path);
  } else {
    // File formats are dispatched here (by extension) once their loaders exist.
    throw Error("cannot load '" + path + "': scene loading arrives with the loaders; use " +
                std::string(kBuiltinHelp));
  }
  scene.name = path;
  return scene;
}

}  // namespace tg::bench
