/// @file SceneSource.h
/// Loading a scene by its file extension, or the built-in demo: what every tool opens.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tracegraph/scenegraph/Node.h"
#include "tracegraph/scenegraph/SceneRenderer.h"
#include "tracegraph/scenegraph/ref_ptr.h"

namespace tg {

/// The frames a scene offers: its own range (BART `a start end N`) or `fps` from time 0.
struct SceneTiming {
  double start = 0.0;
  double end = 0.0;
  int frames = 1;
  /// Time of frame f.
  double timeOf(int f) const {
    return frames <= 1 ? start : start + (end - start) * f / static_cast<double>(frames - 1);
  }
};

/// A loaded scene, ready to put into a SceneGraph.
struct SceneSource {
  std::string name;  ///< file name, or "built-in demo"
  ref_ptr<Node> root;
  SceneLook look;
  SceneTiming timing;
  std::optional<std::pair<std::uint32_t, std::uint32_t>> resolution;  ///< the scene's own
  std::vector<std::filesystem::path> textureFolders;
  std::vector<std::string> warnings;
};

/// Loads `path` by its extension (.aff/.nff, .x3d, anything Assimp reads), or the built-in demo
/// when there is no path. Throws tg::Error naming the file when it cannot be loaded.
SceneSource loadSceneSource(const std::optional<std::string>& path, double fps);

}  // namespace tg
