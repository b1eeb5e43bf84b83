#include "ViewOptions.h"

#include <CLI/CLI.hpp>

#include <iostream>

#include "ToolArgs.h"

namespace tg::view_tool {

bool parseSize(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  return tools::parseImageSizeArgument(text, width, height);
}

std::variant<ViewOptions, int> parseViewOptions(int argc, char** argv) {
  ViewOptions o;
  CLI::App app{
      "tg-view: plays a scene (BART .aff/.nff, .x3d, glTF/OBJ/PLY via Assimp) or, without SCENE, "
      "the built-in demo in a window.\n"
      "Mouse: left drag orbits, right or middle drag pans, wheel zooms. Keys: space play/pause, "
      "right/left arrow step a frame, 1-5 opengl/whitted/normals/classes/instances, t "
      "mip-mapped textures on/off, +/- resolution, Esc or q quit."};
  std::string scene, size, mode = "whitted", accel = "bvh";
  app.add_option("SCENE", scene, "scene file; omitted: the built-in demo scene");
  app.add_option("--size", size, "window size WxH (default: the scene's own, else 640x480)");
  app.add_option("--fps", o.fps, "frame rate of scenes without their own range (default 30)")
      ->check(CLI::PositiveNumber);
  app.add_option("--mode", mode, "opengl|whitted|normals|classes|instances (default whitted)");
  app.add_option("--depth", o.depth, "reflection/refraction depth (default 5)")
      ->check(CLI::Range(0, 64));
  app.add_option("--accel", accel, "bvh|kd: the BVH engine (default) or the paper's kd-trees");
  app.add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--scale", o.scale, "render resolution relative to the window (default 1)")
      ->check(CLI::Range(0.0625, 1.0));
  auto* shot = app.add_option("--screenshot", o.screenshot,
                              "render --frames frames, save the last as a PNG and exit");
  app.add_option("--frames", o.frames, "frames to render before the screenshot (default 1)")
      ->check(CLI::Range(1, 1000000))
      ->needs(shot);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kSuccess : kBadUsage;
  }
  auto usage = [](const std::string& message) {
    std::cerr << "tg-view: " << message << " (see --help)\n";
    return kBadUsage;
  };
  if (!scene.empty()) o.scene = scene;
  if (!size.empty()) {
    if (!parseSize(size, o.width, o.height)) return usage("--size wants WxH, e.g. 640x480");
    o.sizeGiven = true;
  }
  const std::optional<RenderMode> m = parseRenderMode(mode);
  if (!m) return usage("unknown --mode '" + mode + "'");
  if (!parseEngine(accel, o.engine)) return usage("unknown --accel '" + accel + "' (bvh or kd)");
  o.mode = *m;
  return o;
}

}  // namespace tg::view_tool
