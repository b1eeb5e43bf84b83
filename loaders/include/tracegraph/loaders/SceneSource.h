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
  /// Time of the first frame, seconds.
  double start = 0.0;
  /// Time of the last frame, seconds.
  double end = 0.0;
  /// Number of frames, at least 1.
  int frames = 1;
  /// Time of frame f.
  double timeOf(int f) const {
    return frames <= 1 ? start : start + (end - start) * f / static_cast<double>(frames - 1);
  }
};

/// A loaded scene, ready to put into a SceneGraph.
struct SceneSource {
  std::string name;  ///< file name, or "built-in demo"
  /// Root of the scene, for SceneGraph::setRoot.
  ref_ptr<Node> root;
  /// Background and ambient light, from the file.
  SceneLook look;
  /// The frames the scene offers.
  SceneTiming timing;
  std::optional<std::pair<std::uint32_t, std::uint32_t>> resolution;  ///< the scene's own
  /// Where texture names resolve, for SceneRenderer::setTextureSearchPath.
  std::vector<std::filesystem::path> textureFolders;
  /// What the loader dropped or approximated, one line each.
  std::vector<std::string> warnings;
};

/// Loads `path` by its extension (.aff/.nff, .x3d, anything Assimp reads), or the built-in demo
/// when there is no path. Throws tg::Error naming the file when it cannot be loaded.
SceneSource loadSceneSource(const std::optional<std::string>& path, double fps);

}  // namespace tg
