/// @file LoadedScene.h
/// What the X3D and Assimp loaders return: a scene-graph root plus the file-level facts that no
/// node carries (background colour, animation length, warnings).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tracegraph/backend/Vec3.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/ref_ptr.h"

namespace tg {

/// A loaded file, ready for SceneGraph::setRoot(root).
///
/// Animators (time sensors, interpolators, deformers) are reached by the SceneGraph through
/// the connections of the nodes they drive; `animators` lists them all so that tools can
/// inspect them or keep one evaluated that drives nothing in the graph.
struct LoadedScene {
  /// The file as given to the loader (or the name given for in-memory text).
  std::string fileName;
  /// Root of the scene; never null after a successful load (possibly without children).
  ref_ptr<nodes::Separator> root;
  /// Camera nodes in file order; they are also in the graph, where the first in traversal
  /// order is the one SceneGraph::camera() returns (X3D's first bound Viewpoint).
  std::vector<ref_ptr<nodes::Camera>> cameras;
  /// Background colour (X3D Background skyColor[0]); black when the file has none.
  Vec3f background{0.0f, 0.0f, 0.0f};
  /// True when the file set `background`.
  bool hasBackground = false;
  /// Seconds after which every animation has reached its end (non-looping) or completed
  /// its first cycle (looping); 0 for a static scene.
  double animationDuration = 0.0;
  /// Every animator the loader created, connected or not.
  std::vector<ref_ptr<Animator>> animators;
  /// Things dropped or approximated while loading, one line each, naming the file (and the
  /// line for XML): unsupported nodes, missing textures, out-of-range indices, ...
  std::vector<std::string> warnings;
  /// Folders where the file's relative texture names resolve (the file's own folder first).
  std::vector<std::filesystem::path> textureFolders;
  /// Title of the scene (X3D WorldInfo title), empty when none.
  std::string title;
};

}  // namespace tg
