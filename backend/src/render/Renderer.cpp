#include "tracegraph/backend/render/Renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <new>
#include <span>
#include <string>
#include <vector>

#if defined(__SSE__) || defined(_M_X64)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define TG_HAVE_MXCSR 1
#endif

#include "Shader.h"
#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

constexpr std::string_view kModeNames[] = {"opengl", "whitted", "normals", "classes", "instances"};

/// Flushes denormals to zero for the lifetime of the object and then restores the previous
/// floating-point mode. Scoped per tile rather than set once per worker thread: tasks may run
/// on the calling thread, whose mode must come back unchanged, and every tile computes under
/// the same mode whichever thread runs it, which keeps images thread-count independent.
class FlushDenormalsScope {
 public:
  explicit FlushDenormalsScope(bool enable) {
#ifdef TG_HAVE_MXCSR
    if (!enable) return;
    saved_ = _mm_getcsr();
    active_ = true;
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#else
    (void)enable;
#endif
  }
  ~FlushDenormalsScope() {
#ifdef TG_HAVE_MXCSR
    if (active_) _mm_setcsr(saved_);
#endif
  }
  FlushDenormalsScope(const FlushDenormalsScope&) = delete;
  FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

 private:
  unsigned saved_ = 0;
  bool active_ = false;
};

/// Pixels [x0, x1) x [y0, y1) of the image.
struct TileRect {
  std::uint32_t x0, y0, x1, y1;
};

/// What one tile counted.
struct TileResult {
  detail::TileCounters counters;
  std::uint64_t triangleTests = 0, nodeVisits = 0;
};

/// Writes one pixel's sample into the frame's images.
void storeSample(const detail::PixelSample& s, bool aovs, std::uint32_t x, std::uint32_t y,
                 Frame& frame) {
  frame.beauty.setRgb(x, y, s.color);
  if (!aovs) return;
  frame.depth.at(x, y) = s.depth;
  frame.normal.setRgb(x, y, s.normal);
  frame.instanceId.at(x, y) = s.instanceId;
  frame.primId.at(x, y) = s.primId;
}

/// Per-thread memory of renderTile, reused from tile to tile.
struct TileScratch {
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  std::vector<std::uint32_t> px, py;
  std::vector<double> planeX, planeY;  ///< Camera::planeX of the tile's columns, planeY of its rows
  std::vector<detail::PixelSample> samples;
  std::vector<std::uint32_t> blockEnds;  ///< one past the last ray of each 4 x 2 block
  detail::WaveScratch wave;
};

/// Traces and shades every pixel of `rect`, writing only those pixels of `frame`. With packets,
/// primary rays go to the scene in 4 x 2 pixel blocks (neighbouring rays, coherent); Whitted
/// mode then shades the whole tile depth by depth, so that its shadow and secondary rays go as
/// packets too. Each pixel comes out as from single rays.
TileResult renderTile(const detail::Shader& shader, const Scene& scene, const Camera& camera,
                      const RenderSettings& settings, const TileRect& rect, TileScratch& scratch,
                      Frame& frame) {
  TileResult result;
  TraversalContext ctx;
  if (!settings.packets) {
    for (std::uint32_t y = rect.y0; y < rect.y1; ++y)
      for (std::uint32_t x = rect.x0; x < rect.x1; ++x)
        storeSample(shader.shadePrimary(camera.primaryRay(x, y), ctx, result.counters),
                    settings.aovs, x, y, frame);
  } else {
    const std::size_t area = static_cast<std::size_t>(rect.x1 - rect.x0) * (rect.y1 - rect.y0);
    scratch.rays.resize(area);
    scratch.hits.resize(area);
    scratch.px.resize(area);
    scratch.py.resize(area);
    scratch.samples.resize(area);
    // Each column's and row's image-plane coordinate once, rather than once per pixel.
    scratch.planeX.resize(rect.x1 - rect.x0);
    scratch.planeY.resize(rect.y1 - rect.y0);
    for (std::uint32_t x = rect.x0; x < rect.x1; ++x)
      scratch.planeX[x - rect.x0] = camera.planeX(static_cast<double>(x) + 0.5);
    for (std::uint32_t y = rect.y0; y < rect.y1; ++y)
      scratch.planeY[y - rect.y0] = camera.planeY(static_cast<double>(y) + 0.5);
    // Pixels in block order: the rays of one 4 x 2 block are consecutive, and the two 4 x 2
    // blocks of each 4 x 4 block follow each other (the scene walks two full packets as one where
    // its kernels can). Every ray of the tile is made before any is traced: rays read back by
    // the packet load right after the stores that wrote them stalled on those stores.
    std::size_t count = 0;
    scratch.blockEnds.clear();
    for (std::uint32_t y4 = rect.y0; y4 < rect.y1; y4 += 4) {
      for (std::uint32_t x0 = rect.x0; x0 < rect.x1; x0 += 4) {
        for (std::uint32_t y0 = y4; y0 < std::min(y4 + 4, rect.y1); y0 += 2) {
          // Lanes in pairs of horizontal neighbours, made together (Camera::rayPairThroughPlane).
          for (std::uint32_t lane = 0; lane < kRayPacketSize; lane += 2) {
            const std::uint32_t x = x0 + lane % 4, y = y0 + lane / 4;
            if (x >= rect.x1 || y >= rect.y1) continue;
            const double sy = scratch.planeY[y - rect.y0];
            scratch.px[count] = x;
            scratch.py[count] = y;
            if (x + 1 < rect.x1) {
              scratch.px[count + 1] = x + 1;
              scratch.py[count + 1] = y;
              camera.rayPairThroughPlane(scratch.planeX[x - rect.x0],
                                         scratch.planeX[x + 1 - rect.x0], sy, &scratch.rays[count]);
              count += 2;
            } else {
              // camera.primaryRay(x, y), bit for bit, made in place (no temporary to copy).
              ::new (static_cast<void*>(&scratch.rays[count++]))
                  Ray(camera.rayThroughPlane(scratch.planeX[x - rect.x0], sy));
            }
          }
          scratch.blockEnds.push_back(static_cast<std::uint32_t>(count));
        }
      }
    }
    // Block by block, two full blocks in a row together: a partial block (at the tile's edge)
    // goes alone, so that every packet the scene makes is one block.
    for (std::size_t b = 0, first = 0; b < scratch.blockEnds.size();) {
      std::size_t end = scratch.blockEnds[b++];
      if (end - first == kRayPacketSize && b < scratch.blockEnds.size() &&
          scratch.blockEnds[b] - end == kRayPacketSize)
        end = scratch.blockEnds[b++];
      scene.intersect(std::span<const Ray>(scratch.rays.data() + first, end - first),
                      std::span<Hit>(scratch.hits.data() + first, end - first), ctx);
      first = end;
    }
    if (shader.shadesByWave()) {
      shader.shadeWhittedTile(scratch.rays.data(), scratch.hits.data(), count, ctx, result.counters,
                              scratch.wave, scratch.samples.data());
    } else if (shader.shadesOpenGlTiles()) {
      shader.shadeOpenGlTile(scratch.rays.data(), scratch.hits.data(), count, result.counters,
                             scratch.samples.data());
    } else {
      // Made in place: a returned sample copied in was read back before its stores completed.
      for (std::size_t k = 0; k < count; ++k)
        ::new (static_cast<void*>(&scratch.samples[k])) detail::PixelSample(
            shader.shadePrimaryHit(scratch.rays[k], scratch.hits[k], ctx, result.counters));
    }
    for (std::size_t k = 0; k < count; ++k)
      storeSample(scratch.samples[k], settings.aovs, scratch.px[k], scratch.py[k], frame);
  }
  result.triangleTests = ctx.triangleTests;
  result.nodeVisits = ctx.nodeVisits;
  return result;
}

void checkSettings(const RenderSettings& s) {
  if (s.tileSize == 0) throw Error("Renderer::render: tile size is 0");
  if (s.maxDepth < 0) throw Error("Renderer::render: negative maximum depth");
  if (!(s.minWeight >= 0.0f)) throw Error("Renderer::render: ray-weight cutoff is negative or NaN");
  if (static_cast<std::size_t>(s.mode) >= std::size(kModeNames))
    throw Error("Renderer::render: unknown mode");
}

}  // namespace

std::string_view renderModeName(RenderMode mode) {
  const auto i = static_cast<std::size_t>(mode);
  return i < std::size(kModeNames) ? kModeNames[i] : "unknown";
}

std::optional<RenderMode> parseRenderMode(std::string_view name) {
  for (std::size_t i = 0; i < std::size(kModeNames); ++i)
    if (kModeNames[i] == name) return static_cast<RenderMode>(i);
  return std::nullopt;
}

RenderStats Renderer::render(const RenderScene& scene, const Camera& camera, Frame& frame) const {
  checkSettings(settings_);
  const std::string problem = scene.validate();
  if (!problem.empty()) throw Error("Renderer::render: " + problem);

  const std::uint32_t w = camera.width(), h = camera.height();
  // Every pixel of every image is written below, so images of the right size are reused as
  // they are: an animation renders into the same memory frame after frame.
  const auto fits = [&](const auto& image) { return image.width() == w && image.height() == h; };
  if (!fits(frame.beauty) || frame.beauty.channels() != 3) frame.beauty = Image(w, h, 3);
  if (settings_.aovs) {
    if (!fits(frame.depth) || frame.depth.channels() != 1) frame.depth = Image(w, h, 1, kInfinity);
    if (!fits(frame.normal) || frame.normal.channels() != 3) frame.normal = Image(w, h, 3);
    if (!fits(frame.instanceId)) frame.instanceId = IdImage(w, h, kInvalidId);
    if (!fits(frame.primId)) frame.primId = IdImage(w, h, kInvalidId);
  } else {
    frame.depth = Image();
    frame.normal = Image();
    frame.instanceId = IdImage();
    frame.primId = IdImage();
  }

  const detail::Shader shader(scene, settings_, camera.pixelSpreadAngle());
  const std::uint32_t ts = settings_.tileSize;
  const std::uint32_t tilesX = (w + ts - 1) / ts, tilesY = (h + ts - 1) / ts;
  const std::size_t tileCount = static_cast<std::size_t>(tilesX) * tilesY;
  // One slot per tile, written once by the task that rendered it and summed afterwards in
  // tile order: integer sums, so the totals do not depend on the thread count either.
  std::vector<TileResult> results(tileCount);

  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tileCount, 1),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const FlushDenormalsScope flush(settings_.flushDenormals);
                      TileScratch scratch;
                      for (std::size_t tile = range.begin(); tile != range.end(); ++tile) {
                        const std::uint32_t x0 = static_cast<std::uint32_t>(tile % tilesX) * ts;
                        const std::uint32_t y0 = static_cast<std::uint32_t>(tile / tilesX) * ts;
                        const TileRect rect{x0, y0, std::min(x0 + ts, w), std::min(y0 + ts, h)};
                        results[tile] = renderTile(shader, *scene.scene, camera, settings_, rect,
                                                   scratch, frame);
                      }
                    });
  const auto end = std::chrono::steady_clock::now();

  RenderStats stats;
  stats.width = w;
  stats.height = h;
  stats.threads = tbb::this_task_arena::max_concurrency();
  stats.traceShadeMs = std::chrono::duration<double, std::milli>(end - start).count();
  for (const TileResult& r : results) {
    stats.traced += r.counters.traced;
    stats.saved += r.counters.saved;
    stats.depthLimited += r.counters.depthLimited;
    stats.weightCutoff += r.counters.weightCutoff;
    stats.totalInternalReflections += r.counters.totalInternalReflections;
    stats.triangleTests += r.triangleTests;
    stats.nodeVisits += r.nodeVisits;
  }
  if (stats.traceShadeMs > 0.0)
    stats.mraysPerSecond =
        static_cast<double>(stats.traced.total()) / (stats.traceShadeMs * 1000.0);
  return stats;
}

}  // namespace tg
