#include "tracegraph/loaders/SceneSource.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/loaders/AssimpLoader.h"
#include "tracegraph/loaders/DemoScene.h"
#include "tracegraph/loaders/X3dLoader.h"

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

/// The parts of an X3D or Assimp load that every tool needs.
void takeLoadedScene(LoadedScene&& loaded, double fps, SceneSource& s) {
  s.root = loaded.root;
  if (loaded.hasBackground) s.look.background = loaded.background;
  // Formats without their own frame range play their animations from time 0 at `fps`; a
  // static file is one frame.
  s.timing = loaded.animationDuration > 0.0 ? timingFromDuration(loaded.animationDuration, fps)
                                            : SceneTiming{};
  s.textureFolders = std::move(loaded.textureFolders);
  s.warnings = std::move(loaded.warnings);
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
    AffScene aff;
    try {
      aff = loadAff(file);
    } catch (const Error& affError) {
      if (ext != ".nff") throw;
      // Sense8 NFF and Assimp's shorthand shapes (`dod`, `hex`, textured `f`) share the
      // extension with Haines' NFF; Assimp reads those. When it cannot either, the BART
      // reader's message (with its line) is the more useful one.
      try {
        takeLoadedScene(loadAssimp(file), fps, s);
      } catch (const Error&) {
        throw affError;
      }
      s.warnings.insert(s.warnings.begin(),
                        std::string(affError.what()) +
                            " (not Haines/BART NFF; read as Sense8 NFF through Assimp)");
      return s;
    }
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
  if (ext == ".x3d") {
    takeLoadedScene(loadX3d(file), fps, s);
    return s;
  }
  // Assimp itself is asked, so every format of the installed version is accepted.
  if (!ext.empty() && assimpCanRead(ext)) {
    takeLoadedScene(loadAssimp(file), fps, s);
    return s;
  }
  throw Error(*path + ": no loader for '" + ext +
              "' files (known: .aff, .nff, .x3d, and the formats of Assimp: .gltf, .glb, "
              ".obj, .ply, ...)");
}

}  // namespace tg
