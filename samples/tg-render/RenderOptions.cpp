#include "RenderOptions.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>

#include "ToolArgs.h"

namespace tg::render_tool {
namespace {

bool parseSize(const std::string& text, std::uint32_t& w, std::uint32_t& h) {
  return tools::parseImageSizeArgument(text, w, h);
}

bool parseRange(const std::string& text, std::pair<int, int>& range) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) return false;
  try {
    std::size_t used = 0;
    range.first = std::stoi(text.substr(0, colon), &used);
    if (used != colon) return false;
    range.second = std::stoi(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) return false;
  } catch (const std::exception&) {
    return false;
  }
  return range.first >= 0 && range.second >= range.first;
}

}  // namespace

std::variant<RenderOptions, int> parseRenderOptions(int argc, char** argv) {
  RenderOptions o;
  CLI::App app{
      "tg-render: renders frames of a scene (BART .aff/.nff, .x3d, glTF/OBJ/PLY via "
      "Assimp) or, without SCENE, the built-in demo"};
  std::string scene, size, frames, mode = "whitted", aovs, accel = "bvh", filter = "bilinear";
  int frame = -1;
  double time = 0.0;
  app.add_option("SCENE", scene, "scene file; omitted: the built-in demo scene");
  app.add_option("-o,--output", o.output, "output image (PNG); several frames add _NNNN");
  app.add_option("--size", size, "image size WxH (default: the scene's own, else 640x480)");
  auto* frameOpt = app.add_option("--frame", frame, "render frame N of the scene's animation");
  auto* framesOpt = app.add_option("--frames", frames, "render frames A:B (inclusive)");
  auto* timeOpt = app.add_option("--time", time, "render the scene at time T (seconds)");
  frameOpt->excludes(framesOpt)->excludes(timeOpt);
  framesOpt->excludes(timeOpt);
  app.add_option("--fps", o.fps, "frame rate of scenes without their own range (default 30)")
      ->check(CLI::PositiveNumber);
  app.add_option("--mode", mode, "opengl|whitted|normals|classes|instances (default whitted)");
  app.add_option("--depth", o.depth, "reflection/refraction depth (default 5)")
      ->check(CLI::Range(0, 64));
  app.add_option("--accel", accel, "bvh|kd: the BVH engine (default) or the paper's kd-trees");
  app.add_option("--aov", aovs, "comma-separated AOVs: depth,normal,instance,prim");
  app.add_option("--texture-filter", filter,
                 "nearest|bilinear|trilinear: texture lookups; trilinear mip-maps by each "
                 "primary ray's footprint (default bilinear)");
  app.add_option("--stats", o.statsFile, "write per-frame statistics as JSON to FILE");
  app.add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--video", o.video, "also encode the frames to a video with ffmpeg");
  app.add_flag("--quiet", o.quiet, "no progress bar and no summary line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kSuccess : kBadUsage;
  }
  auto usage = [](const std::string& message) {
    std::cerr << "tg-render: " << message << " (see --help)\n";
    return kBadUsage;
  };
  if (!scene.empty()) o.scene = scene;
  if (!size.empty()) {
    if (!parseSize(size, o.width, o.height)) return usage("--size wants WxH, e.g. 640x480");
    o.sizeGiven = true;
  }
  if (*frameOpt) {
    if (frame < 0) return usage("--frame wants a frame number >= 0");
    o.frame = frame;
  }
  if (*framesOpt) {
    std::pair<int, int> range;
    if (!parseRange(frames, range)) return usage("--frames wants A:B with 0 <= A <= B");
    o.frames = range;
  }
  if (*timeOpt) o.time = time;
  const std::optional<RenderMode> m = parseRenderMode(mode);
  if (!m) return usage("unknown --mode '" + mode + "'");
  if (!parseEngine(accel, o.engine)) return usage("unknown --accel '" + accel + "' (bvh or kd)");
  o.mode = *m;
  if (filter == "nearest")
    o.textureFilter = TextureFilter::Nearest;
  else if (filter == "bilinear")
    o.textureFilter = TextureFilter::Bilinear;
  else if (filter == "trilinear")
    o.textureFilter = TextureFilter::Trilinear;
  else
    return usage("unknown --texture-filter '" + filter + "' (nearest, bilinear or trilinear)");
  std::stringstream list(aovs);
  for (std::string item; std::getline(list, item, ',');) {
    if (item == "depth")
      o.aovs.depth = true;
    else if (item == "normal")
      o.aovs.normal = true;
    else if (item == "instance")
      o.aovs.instance = true;
    else if (item == "prim")
      o.aovs.prim = true;
    else if (!item.empty())
      return usage("unknown AOV '" + item + "'");
  }
  return o;
}

}  // namespace tg::render_tool
