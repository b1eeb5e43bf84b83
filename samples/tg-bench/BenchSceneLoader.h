/// @file BenchSceneLoader.h
/// Turns the --scene argument of the build and trace suites into a BenchScene.
#pragma once

#include <string>

#include "BenchScene.h"

namespace tg::bench {

/// Loads the scene named by `path`:
///  - "builtin:sphereflake" or "builtin:sphereflake:D": Haines' sphereflake of depth D
///    (default 3: 820 instances of one sphere) on a ground square;
///  - "builtin:random:N": N random triangles at unit density in one mesh.
/// Any other path is a scene file. The file loaders (BART first) plug in here, converting their
/// scene graph to the flat mesh + instance form; until then a file path is rejected.
/// Throws tg::Error with a message naming the path for anything it cannot load.
BenchScene loadBenchScene(const std::string& path);

}  // namespace tg::bench
