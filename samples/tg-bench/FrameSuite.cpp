// The frame suite (issue "Renderer"): frames per second and rays per second, by ray kind, of
// whole animation frames of a scene -- animators, SceneGraph::sync, SceneRenderer::update and
// render -- as a user of tg-render sees them. There is no peer: Embree traces rays but does
// not shade or animate, and the trace suite compares the traversal alone.
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "BenchTiming.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/render/Renderer.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

namespace tg::bench {
namespace {

/// Frame rate for scenes without their own frame range (the demo), as tg-render's default.
constexpr double kFps = 30.0;

/// `count` frame numbers spread evenly over [0, frames - 1], first and last included.
std::vector<int> spreadFrames(int frames, int count) {
  std::vector<int> out;
  for (int i = 0; i < count; ++i) {
    const double at =
        count == 1 ? 0.0 : static_cast<double>(i) * (frames - 1) / static_cast<double>(count - 1);
    out.push_back(static_cast<int>(std::lround(at)));
  }
  return out;
}

std::string joinFrames(const std::vector<int>& frames) {
  std::string text;
  for (const int f : frames) {
    if (!text.empty()) text += ',';
    text += std::to_string(f);
  }
  return text;
}

/// Samples per pixel and axis of the reference frames that judge aliasing.
constexpr std::uint32_t kJudgeSamples = 4;

/// PSNR in dB of `image` against `fine`, an image kJudgeSamples times as wide and high of the
/// same view, averaged over each pixel's samples: linear values clamped to [0, 1], peak 1.
/// Infinite when they agree exactly.
double psnrAgainstSupersampled(const Image& image, const Image& fine) {
  const std::uint32_t s = kJudgeSamples;
  double squared = 0.0;
  for (std::uint32_t y = 0; y < image.height(); ++y)
    for (std::uint32_t x = 0; x < image.width(); ++x)
      for (std::uint32_t c = 0; c < image.channels(); ++c) {
        double mean = 0.0;
        for (std::uint32_t j = 0; j < s; ++j)
          for (std::uint32_t i = 0; i < s; ++i)
            mean += std::clamp(static_cast<double>(fine.at(s * x + i, s * y + j, c)), 0.0, 1.0);
        mean /= static_cast<double>(s * s);
        const double e = std::clamp(static_cast<double>(image.at(x, y, c)), 0.0, 1.0) - mean;
        squared += e * e;
      }
  const double mse = squared / static_cast<double>(image.data().size());
  return mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

/// Mean per frame of a count summed over `frames` frames.
std::int64_t perFrame(std::uint64_t total, int frames) {
  return static_cast<std::int64_t>((total + static_cast<std::uint64_t>(frames) / 2) /
                                   static_cast<std::uint64_t>(frames));
}

void runMode(BenchReport& report, const SceneSource& source, const FrameSuiteOptions& options,
             const std::string& modeName, const std::string& engineName, int passes) {
  Engine engine = Engine::Bvh;
  if (!parseEngine(engineName, engine))
    throw Error("frame suite: unknown engine '" + engineName + "' (bvh or kd)");
  const std::optional<RenderMode> mode = parseRenderMode(modeName);
  if (!mode || (*mode != RenderMode::OpenGL && *mode != RenderMode::Whitted))
    throw Error("frame suite: unknown mode '" + modeName + "' (opengl or whitted)");
  RenderSettings settings;
  settings.mode = *mode;
  settings.maxDepth = options.depth;
  // tg-render fills the AOVs only when asked for them; the benchmark measures the beauty image.
  settings.aovs = false;
  const std::string& filter = options.textureFilter;
  if (filter == "nearest")
    settings.textureFilter = TextureFilter::Nearest;
  else if (filter == "trilinear")
    settings.textureFilter = TextureFilter::Trilinear;
  else if (filter != "bilinear")
    throw Error("frame suite: unknown texture filter '" + filter + "'");

  const std::vector<int> frames = spreadFrames(source.timing.frames, options.frames);
  const int count = static_cast<int>(frames.size());
  const auto width = static_cast<std::uint32_t>(options.size.width);
  const auto height = static_cast<std::uint32_t>(options.size.height);
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  std::string caseName = source.name + " " + size + " " + modeName;
  if (*mode == RenderMode::Whitted) caseName += " depth " + std::to_string(options.depth);
  std::string impl = "tracegraph-" + engineName + "-" + modeName;
  if (filter != "bilinear") impl += "-" + filter;
  progress("frame: " + impl);

  // A graph and renderer of its own per mode, so that every mode starts from the same state.
  SyncOptions syncOptions;
  syncOptions.scene = sceneOptionsFor(engine);
  SceneGraph graph(syncOptions);
  graph.setRoot(source.root);
  SceneRenderer renderer(graph, settings);
  renderer.setLook(source.look);
  renderer.setTextureSearchPath(source.textureFolders);
  Frame frame;

  double firstFrameMs = 0.0;
  double traceShadeMs = 0.0;
  RayCounts traced, saved;
  std::vector<double> syncMs, renderMs;
  // The warm-up renders the last frame (and pays the initial build of every object, reported
  // separately); the samples then cycle through all the frames, so that each one follows a
  // different frame and its sync sees real changes.
  const TimingSummary t = measureRepeated(count * passes, [&](int k) {
    const int f = k == 0 ? frames.back() : frames[static_cast<std::size_t>((k - 1) % count)];
    FrameStats stats;
    RenderStats r;
    const double ms = timeMs([&] {
      graph.advanceTo(source.timing.timeOf(f));
      stats = graph.sync();
      renderer.update();
      r = renderer.render(renderer.camera(width, height), frame, &stats);
    });
    if (k == 0) {
      firstFrameMs = ms;
    } else {
      traceShadeMs += r.traceShadeMs;
      traced += r.traced;
      saved += r.saved;
      syncMs.push_back(stats.syncMs);
      renderMs.push_back(r.traceShadeMs);
    }
    return ms;
  });

  const int samples = count * passes;
  BenchRow& row = addRow(report, caseName, impl, t);
  // rays / (ms * 1e-3 s/ms) / 1e6 rays per Mray, over the renderer's trace-and-shade time, as
  // tg-render reports it.
  if (traceShadeMs > 0.0)
    row.mraysPerS = static_cast<double>(traced.total()) / (traceShadeMs * 1e3);
  row.extra.push_back(realField("fps", t.medianMs > 0.0 ? 1000.0 / t.medianMs : 0.0));
  row.extra.push_back(realField("sync_ms", summarize(syncMs).medianMs));
  row.extra.push_back(realField("render_ms", summarize(renderMs).medianMs));
  row.extra.push_back(realField("first_frame_ms", firstFrameMs));
  // Rays per frame (mean over the samples), by kind; "saved" are those the renderer showed to
  // be useless and did not trace (Whitted mode only).
  row.extra.push_back(intField("primary", perFrame(traced.primary, samples)));
  row.extra.push_back(intField("shadow", perFrame(traced.shadow, samples)));
  row.extra.push_back(intField("reflection", perFrame(traced.reflection, samples)));
  row.extra.push_back(intField("refraction", perFrame(traced.refraction, samples)));
  row.extra.push_back(intField("saved_shadow", perFrame(saved.shadow, samples)));
  row.extra.push_back(intField("saved_reflection", perFrame(saved.reflection, samples)));
  row.extra.push_back(intField("saved_refraction", perFrame(saved.refraction, samples)));
  if (*mode == RenderMode::Whitted) row.extra.push_back(intField("depth", options.depth));
  row.extra.push_back(textField("frames", joinFrames(frames)));
  // The error of a frame: the last frame rendered again with the suite's threads and with one
  // thread must be bit-identical (hard case 21); the count of differing beauty values is
  // reported.
  Frame many, one;
  const Camera camera = renderer.camera(width, height);
  renderer.render(camera, many);
  tbb::task_arena single(1);
  single.execute([&] { renderer.render(camera, one); });
  std::int64_t differing = 0;
  for (std::size_t i = 0; i < many.beauty.data().size(); ++i)
    differing += std::memcmp(&many.beauty.data()[i], &one.beauty.data()[i], sizeof(float)) != 0;
  row.extra.push_back(intField("threads_diff_values", differing));
  // And what one sample per pixel costs in aliasing (minified textures, edges): the PSNR of
  // the frame against the same frame with 4 x 4 samples per pixel. The engines give the same
  // images, so only the BVH's rows pay for the 16 times larger render.
  if (engine == Engine::Bvh) {
    Frame fine;
    renderer.render(renderer.camera(kJudgeSamples * width, kJudgeSamples * height), fine);
    row.extra.push_back(
        realField("psnr_vs_16spp_db", psnrAgainstSupersampled(many.beauty, fine.beauty)));
  }
  for (const std::string& w : renderer.warnings()) progress("warning: " + w);
}

}  // namespace

BenchReport runFrameSuite(const CommonOptions& common, const FrameSuiteOptions& options) {
  const int passes = repsOrDefault(common, kDefaultFramePasses);
  if (options.frames < 1) throw Error("frame suite: --frames must be at least 1");
  const SceneSource source = loadSceneSource(options.scene, kFps);
  for (const std::string& w : source.warnings) progress("warning: " + w);
  BenchReport report = startReport("frame", common);
  for (const std::string& mode : options.modes)
    for (const std::string& engine : options.engines)
      runMode(report, source, options, mode, engine, passes);
  return report;
}

}  // namespace tg::bench
