#include "tracegraph/loaders/SceneSource.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/loaders/DemoScene.h"

namespace tg {
namespace {

std::string lowerExtension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

/// Frames at `fps` covering [0, duration].
SceneTiming timingFromDuration(double duration, double fps) {
  SceneTiming t;
  t.start = 0.0;
  t.frames = std::max(1, static_cast<int>(std::floor(duration * fps + 1e-9)) + 1);
  t.end = (t.frames - 1) / fps;
  return t;
}

}  // namespace

SceneSource loadSceneSource(const std::optional<std::string>& path, double fps) {
  SceneSource s;
  if (!path) {
    DemoScene demo = makeDemoScene();
    s.name = "built-in demo";
    s.root = demo.root;
    s.look = demo.look;
    // One loop of the demo; the last frame would repeat the first.
    s.timing = timingFromDuration(demo.duration - 1.0 / fps, fps);
    return s;
  }
  const std::filesystem::path file(*path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw Error(*path + ": no such file");
  s.name = file.filename().string();
  const std::string ext = lowerExtension(file);
  if (ext == ".aff" || ext == ".nff") {
    AffScene aff = loadAff(file);
    s.root = aff.root;
    s.look = aff.look();
    // BART's `a start end N` is the scene's own frame range; files without it animate from 0.
    s.timing = aff.animation.present
                   ? SceneTiming{aff.animation.start, aff.animation.end, aff.animation.frames}
                   : SceneTiming{};
    if (aff.width > 0 && aff.height > 0)
      s.resolution = {static_cast<std::uint32_t>(aff.width),
                      static_cast<std::uint32_t>(aff.height)};
    s.textureFolders = aff.textureFolders;
    s.warnings = std::move(aff.warnings);
    return s;
  }
  throw Error(*path + ": no loader for '" + ext + "' files (known: .aff, .nff)");
}

}  // namespace tg
