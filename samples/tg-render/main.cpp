// tg-render: renders frames of a scene file, or of the built-in demo, to images.
//
//   tg-render [SCENE] [-o OUT.png] [--size WxH] [--frame N | --frames A:B | --time T]
//             [--mode opengl|whitted|normals|classes|instances] [--depth D]
//             [--aov depth,normal,instance,prim] [--texture-filter nearest|bilinear|trilinear]
//             [--stats FILE.json] [--threads N]
//             [--video OUT.mp4] [--quiet]
//
// Exit codes: 0 success, 1 bad input (the message names the file), 2 bad usage.

#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

#include "FrameOutput.h"
#include "ProgressBar.h"
#include "RenderOptions.h"
#include "ToolThreads.h"
#include "VideoPipe.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

using namespace tg;
using namespace tg::render_tool;

namespace {

/// The clock times to render, from --frame / --frames / --time and the scene's timing.
bool frameTimes(const RenderOptions& o, const SceneTiming& timing, std::vector<double>& times,
                std::vector<int>& numbers) {
  if (o.time) {
    times.push_back(*o.time);
    numbers.push_back(0);
    return true;
  }
  int first = 0, last = 0;
  if (o.frame) first = last = *o.frame;
  if (o.frames) std::tie(first, last) = *o.frames;
  if (last >= timing.frames) {
    std::cerr << "tg-render: frame " << last << " is beyond the scene's " << timing.frames
              << " frames (0.." << timing.frames - 1 << ")\n";
    return false;
  }
  for (int f = first; f <= last; ++f) {
    times.push_back(timing.timeOf(f));
    numbers.push_back(f);
  }
  return true;
}

int run(const RenderOptions& o) {
  SceneSource source;
  try {
    source = loadSceneSource(o.scene, o.fps);
  } catch (const Error& e) {
    std::cerr << "tg-render: " << e.what() << "\n";
    return kBadInput;
  }
  for (const std::string& w : source.warnings) std::cerr << "tg-render: warning: " << w << "\n";
  std::vector<double> times;
  std::vector<int> numbers;
  if (!frameTimes(o, source.timing, times, numbers)) return kBadUsage;
  std::uint32_t width = o.width, height = o.height;
  if (!o.sizeGiven && source.resolution) std::tie(width, height) = *source.resolution;

  SyncOptions syncOptions;
  syncOptions.scene = sceneOptionsFor(o.engine);
  SceneGraph graph(syncOptions);
  graph.setRoot(source.root);
  RenderSettings settings;
  settings.mode = o.mode;
  settings.maxDepth = o.depth;
  settings.textureFilter = o.textureFilter;
  settings.aovs = o.aovs.any();
  SceneRenderer renderer(graph, settings);
  renderer.setLook(source.look);
  renderer.setTextureSearchPath(source.textureFolders);

  const bool numbered = times.size() > 1;
  const FrameNaming naming(o.output, numbered);
  std::unique_ptr<VideoPipe> video;
  std::vector<FrameStats> allStats;
  Frame frame;
  std::uint64_t rays = 0;
  double renderMs = 0.0;
  const auto start = std::chrono::steady_clock::now();
  try {
    if (!o.video.empty()) video = std::make_unique<VideoPipe>(o.video, width, height, o.fps);
    ProgressBar progress(static_cast<int>(times.size()), !o.quiet);
    for (std::size_t i = 0; i < times.size(); ++i) {
      graph.advanceTo(times[i]);
      FrameStats stats = graph.sync();
      renderer.update();
      renderer.render(renderer.camera(width, height), frame, &stats);
      writeFrame(frame, naming, numbers[i], o.aovs);
      if (video) video->write(frame.beauty);
      rays += stats.rays.total();
      renderMs += stats.renderMs;
      allStats.push_back(stats);
      progress.update(static_cast<int>(i + 1));
    }
    if (video) video->finish();
  } catch (const std::exception& e) {
    // tg::Error names the file; anything else (out of memory, filesystem) is still reported
    // as bad input rather than a crash.
    std::cerr << "tg-render: " << e.what() << "\n";
    return kBadInput;
  }
  for (const std::string& w : renderer.warnings()) std::cerr << "tg-render: warning: " << w << "\n";
  if (!o.statsFile.empty()) {
    std::ofstream out(o.statsFile);
    out << "{\"frames\": [";
    for (std::size_t i = 0; i < allStats.size(); ++i)
      out << (i ? ",\n  " : "\n  ") << toJson(allStats[i]);
    out << "\n]}\n";
    if (!out) {
      std::cerr << "tg-render: " << o.statsFile << ": cannot write statistics\n";
      return kBadInput;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!o.quiet)
    std::cerr << "tg-render: " << source.name << ", " << times.size() << " frame"
              << (times.size() == 1 ? "" : "s") << " " << width << "x" << height << " "
              << renderModeName(o.mode) << " in " << seconds << " s: " << times.size() / seconds
              << " fps, " << (renderMs > 0.0 ? rays / (renderMs * 1e3) : 0.0) << " Mrays/s, wrote "
              << naming.image(numbers.front()) << (numbered ? " ..." : "") << "\n";
  return kSuccess;
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = parseRenderOptions(argc, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const RenderOptions& o = std::get<RenderOptions>(parsed);
  return tools::runWithThreads(o.threads, [&] { return run(o); });
}
