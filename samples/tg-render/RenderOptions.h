// Command line of tg-render (the interface shared by every tool, test and benchmark).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/render/Renderer.h"

namespace tg::render_tool {

/// Exit codes: 0 success, 1 bad input (the message names the file), 2 bad usage.
enum ExitCode : int { kSuccess = 0, kBadInput = 1, kBadUsage = 2 };

/// The AOVs that can be written beside the image.
struct AovSelection {
  bool depth = false, normal = false, instance = false, prim = false;
  bool any() const { return depth || normal || instance || prim; }
};

/// Everything the command line sets.
struct RenderOptions {
  std::optional<std::string> scene;  ///< empty: the built-in demo
  std::string output = "out.png";
  std::uint32_t width = 640, height = 480;
  bool sizeGiven = false;
  std::optional<int> frame;                   ///< --frame N
  std::optional<std::pair<int, int>> frames;  ///< --frames A:B (inclusive)
  std::optional<double> time;                 ///< --time T (seconds)
  double fps = 30.0;                          ///< frame rate for scenes without their own range
  RenderMode mode = RenderMode::Whitted;
  int depth = 5;
  TextureFilter textureFilter = TextureFilter::Bilinear;  ///< --texture-filter
  Engine engine = Engine::Bvh;                            ///< --accel kd|bvh
  AovSelection aovs;
  std::string statsFile;
  int threads = 0;  ///< 0: all cores
  std::string video;
  bool quiet = false;
};

/// Parses argv. Returns the options, or an exit code after printing help (0) or an error (2).
std::variant<RenderOptions, int> parseRenderOptions(int argc, char** argv);

}  // namespace tg::render_tool
