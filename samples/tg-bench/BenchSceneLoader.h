/// @file BenchSceneLoader.h
/// Turns the --scene argument of the build and trace suites into a BenchScene.
#pragma once

#include <string>

#include "BenchScene.h"

namespace tg {
class SceneGraph;
}

namespace tg::bench {

/// Loads the scene named by `path`:
///  - "builtin:sphereflake" or "builtin:sphereflake:D": Haines' sphereflake of depth D
///    (default 3: 820 instances of one sphere) on a ground square;
///  - "builtin:random:N": N random triangles at unit density in one mesh.
///  - a file ending in .aff or .nff (BART / NFF): loaded with tg::loadAff into a SceneGraph,
///    advanced to the first frame of its animation, synced, and flattened with
///    flattenSyncedScene (static chunks in world space, rigid and deforming parts as the
///    objects and instance matrices of that frame).
/// Other files are rejected. Throws tg::Error with a message naming the path (and, for scene
/// files, the line) for anything it cannot load.
BenchScene loadBenchScene(const std::string& path);

/// True when `path` ends in .aff or .nff (any case).
bool isAffPath(const std::string& path);

/// The synced backend scene of `graph` as meshes and instances: one mesh per backend object
/// used by an instance (in first-use order), one BenchInstance per backend instance with its
/// matrix.
BenchScene flattenSyncedScene(const SceneGraph& graph);

}  // namespace tg::bench
