// Command line of tg-view (same SCENE/--size/--mode/--threads conventions as tg-render).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/render/Renderer.h"

namespace tg::view_tool {

/// Exit codes: 0 success, 1 bad input (the message names the file), 2 bad usage.
enum ExitCode : int { kSuccess = 0, kBadInput = 1, kBadUsage = 2 };

/// Everything the command line sets.
struct ViewOptions {
  std::optional<std::string> scene;         ///< empty: the built-in demo
  std::uint32_t width = 640, height = 480;  ///< initial window size
  bool sizeGiven = false;
  double fps = 30.0;  ///< frame rate of scenes without their own range
  RenderMode mode = RenderMode::Whitted;
  int depth = 5;
  Engine engine = Engine::Bvh;  ///< --accel kd|bvh
  int threads = 0;              ///< 0: all cores
  double scale = 1.0;           ///< render resolution / window resolution
  std::string screenshot;       ///< non-empty: render `frames` frames, save the last, exit
  int frames = 1;
};

/// Parses argv. Returns the options, or an exit code after printing help (0) or an error (2).
std::variant<ViewOptions, int> parseViewOptions(int argc, char** argv);

/// Parses "WxH" (each 1..16384); false when malformed.
bool parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height);

}  // namespace tg::view_tool
