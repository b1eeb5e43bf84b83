// The trace suite: ray throughput of closest-hit (primary) and any-hit (shadow) queries on the
// same rays for every implementation, with a hit-by-hit comparison as an accuracy check.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "FlattenedScene.h"
#include "HitComparison.h"
#include "ImageJudge.h"
#include "RayGenerators.h"
#include "ReferenceJudge.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "TraceParallel.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/Simd.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {
namespace {

/// The work of one trace, summed over its tasks' traversal contexts: node visits (a packet's
/// visit counts once, for all its lanes) and watertight triangle tests (one per lane).
struct WalkCounts {
  std::atomic<std::uint64_t> nodeVisits{0};
  std::atomic<std::uint64_t> triangleTests{0};

  /// Adds a task's context, when counting (`counts` not null).
  static void add(WalkCounts* counts, const TraversalContext& ctx) {
    if (counts == nullptr) return;
    counts->nodeVisits.fetch_add(ctx.nodeVisits, std::memory_order_relaxed);
    counts->triangleTests.fetch_add(ctx.triangleTests, std::memory_order_relaxed);
  }
};

/// Traces once more, untimed, with `traceCounted(&counts)`, and adds the work per ray to `row`:
/// node_visits_per_ray and triangle_tests_per_ray.
void addWalkCounts(BenchRow& row, std::size_t rays,
                   const std::function<void(WalkCounts*)>& traceCounted) {
  WalkCounts counts;
  traceCounted(&counts);
  const double n = rays > 0 ? static_cast<double>(rays) : 1.0;
  row.extra.push_back(
      realField("node_visits_per_ray", static_cast<double>(counts.nodeVisits.load()) / n));
  row.extra.push_back(
      realField("triangle_tests_per_ray", static_cast<double>(counts.triangleTests.load()) / n));
}

void traceOurs(const Scene& scene, std::span<const Ray> rays, std::span<RayOutcome> out,
               WalkCounts* counts = nullptr) {
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    TraversalContext ctx;
    Hit hit;
    for (std::size_t i = begin; i < end; ++i) {
      scene.intersect(rays[i], hit, ctx);
      out[i] = {hit.instanceId, hit.primId};
    }
    WalkCounts::add(counts, ctx);
  });
}

/// Any hit per ray, the rays of a task through one context. Without `hints`, every ray starts
/// with no occluder hint (TraversalContext::occluder), as if traced alone: what the engine's
/// walk costs without the coherence of neighbouring rays.
void occludedOurs(const Scene& scene, std::span<const Ray> rays, std::span<std::uint8_t> out,
                  bool hints = true, WalkCounts* counts = nullptr) {
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    TraversalContext ctx;
    for (std::size_t i = begin; i < end; ++i) {
      if (!hints) ctx.occluder = {};
      out[i] = scene.occluded(rays[i], ctx) ? 1 : 0;
    }
    WalkCounts::add(counts, ctx);
  });
}

/// Rays per packet task: 32 packets of 8.
constexpr std::size_t kPacketRaysPerTask = 32 * kRayPacketSize;

/// Closest hits through the packet interface (Scene::intersect over spans): `stream` holds the
/// rays in packet order, out[order[k]] receives the answer of stream[k].
void tracePacketsOurs(const Scene& scene, std::span<const Ray> stream,
                      std::span<const std::uint32_t> order, std::span<RayOutcome> out, bool pairs,
                      WalkCounts* counts = nullptr) {
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(
          0, (stream.size() + kPacketRaysPerTask - 1) / kPacketRaysPerTask),
      [&](const tbb::blocked_range<std::size_t>& r) {
        TraversalContext ctx;
        ctx.pairPackets = pairs;
        Hit hits[kPacketRaysPerTask];
        for (std::size_t task = r.begin(); task != r.end(); ++task) {
          const std::size_t begin = task * kPacketRaysPerTask;
          const std::size_t count = std::min(kPacketRaysPerTask, stream.size() - begin);
          scene.intersect(stream.subspan(begin, count), std::span<Hit>(hits, count), ctx);
          for (std::size_t k = 0; k < count; ++k)
            out[order[begin + k]] = {hits[k].instanceId, hits[k].primId};
        }
        WalkCounts::add(counts, ctx);
      });
}

/// Any hit through the packet interface, rays in their given order (consecutive shadow rays
/// leave neighbouring pixels, so each group of eight is coherent).
void occludedPacketsOurs(const Scene& scene, std::span<const Ray> rays, std::span<std::uint8_t> out,
                         bool pairs, WalkCounts* counts = nullptr) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(
                        0, (rays.size() + kPacketRaysPerTask - 1) / kPacketRaysPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      TraversalContext ctx;
                      ctx.pairPackets = pairs;
                      for (std::size_t task = r.begin(); task != r.end(); ++task) {
                        const std::size_t begin = task * kPacketRaysPerTask;
                        const std::size_t count = std::min(kPacketRaysPerTask, rays.size() - begin);
                        scene.occluded(rays.subspan(begin, count), out.subspan(begin, count), ctx);
                      }
                      WalkCounts::add(counts, ctx);
                    });
}

/// Pixel indices in packet order: 4 x 2 blocks (the pixels embree-intersect8 packs in a packet),
/// the two of each 4 x 4 block one after the other (those embree-intersect16 packs, and the
/// pairs of packets our scene walks as one where its kernels can), 4 x 4 blocks row by row;
/// pixels outside the image are left out.
std::vector<std::uint32_t> blockOrder(ImageSize size) {
  std::vector<std::uint32_t> order;
  order.reserve(size.pixels());
  for (int y4 = 0; y4 < size.height; y4 += 4)
    for (int x0 = 0; x0 < size.width; x0 += 4)
      for (int y0 = y4; y0 < std::min(y4 + 4, size.height); y0 += 2)
        for (int lane = 0; lane < 8; ++lane) {
          const int x = x0 + lane % 4, y = y0 + lane / 4;
          if (x < size.width && y < size.height)
            order.push_back(static_cast<std::uint32_t>(y * size.width + x));
        }
  return order;
}

/// Primary hits (distance and normal) for spawning shadow rays; computed once, untimed.
std::vector<SurfaceHit> primaryHits(const Scene& scene, std::span<const Ray> rays) {
  std::vector<SurfaceHit> hits(rays.size());
  parallelOverRays(rays.size(), [&](std::size_t begin, std::size_t end) {
    TraversalContext ctx;
    Hit hit;
    for (std::size_t i = begin; i < end; ++i)
      if (scene.intersect(rays[i], hit, ctx)) hits[i] = {hit.t, hit.geometricNormal};
  });
  return hits;
}

/// A row of the suite: one trace of all the rays inside `arena`, and what is added to its row
/// once every row has been timed (throughput, answer counts, comparisons, judgements).
TimedRow tracedRow(tbb::task_arena& arena, const std::string& caseName, const std::string& impl,
                   std::size_t rayCount, std::function<void()> trace,
                   std::function<void(BenchRow&)> finish) {
  return {caseName, impl,
          [&arena, trace = std::move(trace)] { return timeMs([&] { arena.execute(trace); }); },
          [rayCount, finish = std::move(finish)](BenchRow& row) {
            setRays(row, rayCount);
            finish(row);
          }};
}

/// Rays of a trace judged by the brute-force reference: a fixed subsample, since the reference
/// tests every triangle for every ray.
constexpr std::size_t kJudgedRays = 1024;

/// Every k-th answer, as subsampleRays selects rays.
std::vector<std::uint8_t> subsampleFlags(std::span<const std::uint8_t> flags, std::size_t count) {
  std::vector<RayOutcome> asOutcomes(flags.size());
  for (std::size_t i = 0; i < flags.size(); ++i)
    if (flags[i]) asOutcomes[i].prim = 0;
  std::vector<std::uint8_t> out;
  for (const RayOutcome& o : subsampleOutcomes(asOutcomes, count)) out.push_back(o.hit() ? 1 : 0);
  return out;
}

[[maybe_unused]] void addMismatches(BenchRow& row, const MismatchCounts& counts, bool withPrim) {
  row.extra.push_back(intField("hit_mismatches", static_cast<std::int64_t>(counts.hitMiss)));
  if (withPrim)
    row.extra.push_back(intField("prim_mismatches", static_cast<std::int64_t>(counts.prim)));
}

/// The scene `options` names, flattened into one mesh when asked (its camera kept).
BenchScene loadTraceScene(const TraceOptions& options) {
  BenchScene bench = loadBenchScene(options.scene);
  if (!options.flatten) return bench;
  BenchScene flat = flatten(bench).scene;
  flat.camera = bench.camera;
  return flat;
}

}  // namespace

BenchReport runTraceSuite(const CommonOptions& common, const TraceOptions& options) {
  const int reps = repsOrDefault(common, kDefaultTraceReps);
  const bool shadow = options.rays == "shadow";
  const BenchScene bench = loadTraceScene(options);
  BenchReport report = startReport("trace", common);
  const bool sceneView = options.view == "scene";
  if (sceneView && !bench.camera)
    throw Error("trace --view scene: '" + options.scene + "' has no camera of its own");
  const std::string caseName =
      options.scene + " " + options.rays + " " + std::to_string(options.size.width) + "x" +
      std::to_string(options.size.height) + (sceneView ? " scene view" : "") +
      (options.flatten ? " flattened" : "");
  tbb::task_arena arena(common.threads);

  progress("trace: building " + options.scene);
  // The default (BVH) engine and the paper's kd-trees over the same instances.
  Scene scene;
  Scene kdScene(sceneOptionsFor(Engine::KdTree));
  populateScene(bench, scene);
  populateScene(bench, kdScene);
  arena.execute([&] {
    scene.commit();
    kdScene.commit();
  });
  const Box3f bounds = scene.bounds();
  if (bounds.empty()) throw Error("scene '" + options.scene + "' has no triangles to trace");

  const std::vector<Ray> primary =
      sceneView ? makePrimaryRays(*bench.camera, options.size)
                : makePrimaryRays(frameBounds(bounds, options.size), options.size);
  std::vector<Ray> rays;
  if (shadow) {
    std::vector<SurfaceHit> hits;
    arena.execute([&] { hits = primaryHits(scene, primary); });
    // The offset scales with the scene so that it clears float rounding of the hit point.
    const float offset = 1e-4f * 0.5f * length(bounds.extent());
    rays = makeShadowRays(primary, hits, lightAbove(bounds), offset);
  } else {
    rays = primary;
  }
  const std::size_t n = rays.size();

  // The reference's answers for a subsample of the rays; every row is judged on them.
  const std::vector<Ray> judged = subsampleRays(rays, kJudgedRays);
  const ReferenceIntersector reference(scene);
  std::vector<ReferenceHit> expected;
  if (!shadow) arena.execute([&] { expected = referenceHits(reference, judged); });
  // The reference's image on a pixel grid, for the perceptual (FLIP) error of primary rays.
  std::optional<ReferenceImage> image;
  if (!shadow)
    arena.execute([&] { image.emplace(scene, reference, rays, options.size, kJudgedRays); });
  const auto judgeClosest = [&](BenchRow& row, std::span<const RayOutcome> out) {
    const std::vector<RayOutcome> sub = subsampleOutcomes(out, kJudgedRays);
    row.extra.push_back(intField(
        "ref_mismatches", static_cast<std::int64_t>(judgeOutcomes(expected, sub).mismatches)));
    row.extra.push_back(intField("judged", static_cast<std::int64_t>(judged.size())));
    // Eye-light shading of the primary hits against the reference's: an image error.
    row.extra.push_back(realField("psnr_db", eyeLightPsnr(scene, judged, expected, sub)));
    row.extra.push_back(realField("flip_mean", image->flipMean(out)));
  };
  const auto judgeAny = [&](BenchRow& row, std::span<const std::uint8_t> occluded) {
    Judgement j;
    arena.execute(
        [&] { j = judgeOcclusion(reference, judged, subsampleFlags(occluded, kJudgedRays)); });
    row.extra.push_back(intField("ref_mismatches", static_cast<std::int64_t>(j.mismatches)));
    row.extra.push_back(intField("judged", static_cast<std::int64_t>(j.rays)));
  };

  // `ours` holds the default engine's answers, which the peer rows are compared with. Every row
  // writes its own answers, so that the rows can be timed in interleaved rounds and compared
  // afterwards.
  std::vector<RayOutcome> ours(n), kdOutcomes(n);
  std::vector<std::uint8_t> oursOccluded(n), kdOccluded(n), unhinted(n);
  std::vector<TimedRow> rows;
  const auto add = [&](const std::string& impl, std::function<void()> trace,
                       std::function<void(BenchRow&)> finish) {
    rows.push_back(tracedRow(arena, caseName, impl, n, std::move(trace), std::move(finish)));
  };
  const auto countOccluded = [](BenchRow& row, const std::vector<std::uint8_t>& occ) {
    row.extra.push_back(intField("occluded", std::count(occ.begin(), occ.end(), std::uint8_t{1})));
  };
  const auto countHits = [](BenchRow& row, const std::vector<RayOutcome>& out) {
    row.extra.push_back(intField(
        "hits",
        std::count_if(out.begin(), out.end(), [](const RayOutcome& o) { return o.hit(); })));
  };
  struct EngineRows {
    const char* impl;
    const Scene* traced;
    std::vector<RayOutcome>* outcomes;
    std::vector<std::uint8_t>* occluded;
  };
  for (const EngineRows& e : {EngineRows{"tracegraph-bvh", &scene, &ours, &oursOccluded},
                              EngineRows{"tracegraph-kd", &kdScene, &kdOutcomes, &kdOccluded}}) {
    // The loop's array is a temporary: the rows keep pointers, not references into it.
    if (shadow) {
      add(
          e.impl,
          [&rays, traced = e.traced, occ = e.occluded] { occludedOurs(*traced, rays, *occ); },
          [&, traced = e.traced, occ = e.occluded](BenchRow& row) {
            countOccluded(row, *occ);
            addWalkCounts(row, n,
                          [&](WalkCounts* c) { occludedOurs(*traced, rays, *occ, true, c); });
            judgeAny(row, *occ);
          });
    } else {
      add(
          e.impl, [&rays, traced = e.traced, out = e.outcomes] { traceOurs(*traced, rays, *out); },
          [&, traced = e.traced, out = e.outcomes](BenchRow& row) {
            countHits(row, *out);
            addWalkCounts(row, n, [&](WalkCounts* c) { traceOurs(*traced, rays, *out, c); });
            judgeClosest(row, *out);
          });
    }
  }

  // Shadow rays also one by one as if each were alone: the default engine's any-hit walk
  // without the occluder hint that neighbouring rays leave (their answers are the same).
  if (shadow)
    add(
        "tracegraph-bvh-unhinted", [&] { occludedOurs(scene, rays, unhinted, false); },
        [&](BenchRow& row) {
          countOccluded(row, unhinted);
          addWalkCounts(row, n,
                        [&](WalkCounts* c) { occludedOurs(scene, rays, unhinted, false, c); });
          row.extra.push_back(intField(
              "single_ray_mismatches",
              static_cast<std::int64_t>(compareOcclusion(oursOccluded, unhinted).hitMiss)));
          judgeAny(row, unhinted);
        });

  // Packets of 8 (the BVH engine; the kd engine would trace every lane alone). Their answers
  // must equal the single-ray walk's. tracegraph-bvh-packets walks each two neighbouring packets
  // as one where the active kernels can (TraversalContext::pairPackets), tracegraph-bvh-packets8
  // every packet alone: the same kernels, so the pair's gain is their ratio in this run.
  // Primary packets trace 4x2 pixel blocks, the two of each 4x4 block in a row: the block order
  // and the rays in it outlive the rows, which trace them by reference.
  std::vector<std::uint32_t> order;
  std::vector<Ray> stream;
  if (!shadow) {
    order = blockOrder(options.size);
    stream.resize(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) stream[k] = rays[order[k]];
  }
  const auto addPacketRows = [&](const std::string& impl, bool pairs) {
    if (shadow) {
      auto out = std::make_shared<std::vector<std::uint8_t>>(n);
      add(
          impl, [&, out, pairs] { occludedPacketsOurs(scene, rays, *out, pairs); },
          [&, out, pairs](BenchRow& row) {
            countOccluded(row, *out);
            addWalkCounts(row, n,
                          [&](WalkCounts* c) { occludedPacketsOurs(scene, rays, *out, pairs, c); });
            row.extra.push_back(
                intField("single_ray_mismatches",
                         static_cast<std::int64_t>(compareOcclusion(oursOccluded, *out).hitMiss)));
            row.extra.push_back(textField("simd", std::string(simdIsaName(activeSimdIsa()))));
            judgeAny(row, *out);
          });
      return;
    }
    auto out = std::make_shared<std::vector<RayOutcome>>(n);
    add(
        impl, [&, out, pairs] { tracePacketsOurs(scene, stream, order, *out, pairs); },
        [&, out, pairs](BenchRow& row) {
          countHits(row, *out);
          addWalkCounts(row, n, [&](WalkCounts* c) {
            tracePacketsOurs(scene, stream, order, *out, pairs, c);
          });
          const MismatchCounts m = compareOutcomes(ours, *out);
          row.extra.push_back(
              intField("single_ray_mismatches", static_cast<std::int64_t>(m.hitMiss + m.prim)));
          row.extra.push_back(textField("simd", std::string(simdIsaName(activeSimdIsa()))));
          judgeClosest(row, *out);
        });
  };
  addPacketRows("tracegraph-bvh-packets", true);
  addPacketRows("tracegraph-bvh-packets8", false);

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  // Embree's scene at two build qualities, each traced by its own rows: HIGH (spatial splits;
  // the rows without a quality in their name, as since the first reports) and MEDIUM (binned
  // SAH like our static objects, and Embree's default). Neither wins everywhere: from the
  // kitchen's camera MEDIUM traced about 20% faster, from outside the scenes HIGH a few percent.
  // The report holds our rows against the faster of the two.
  struct PeerRows {
    EmbreeQuality quality;
    const char* prefix;
  };
  std::vector<std::unique_ptr<EmbreeBenchScene>> peers;
  for (const PeerRows& p : {PeerRows{EmbreeQuality::High, "embree-"},
                            PeerRows{EmbreeQuality::Medium, "embree-medium-"}}) {
    peers.push_back(std::make_unique<EmbreeBenchScene>(device, bench, p.quality));
    EmbreeBenchScene& peer = *peers.back();
    arena.execute([&] { peer.commit(); });
    device.check("building the scene");
    const std::string prefix = p.prefix;
    if (shadow) {
      auto theirs = std::make_shared<std::vector<std::uint8_t>>(n);
      add(
          prefix + "occluded1", [&peer, &rays, theirs] { peer.occluded1(rays, *theirs); },
          [&, theirs](BenchRow& row) {
            addMismatches(row, compareOcclusion(oursOccluded, *theirs), false);
            judgeAny(row, *theirs);
          });
    } else {
      auto theirs1 = std::make_shared<std::vector<RayOutcome>>(n);
      auto theirs8 = std::make_shared<std::vector<RayOutcome>>(n);
      auto theirs16 = std::make_shared<std::vector<RayOutcome>>(n);
      add(
          prefix + "intersect1", [&peer, &rays, theirs1] { peer.intersect1(rays, *theirs1); },
          [&, theirs1](BenchRow& row) {
            addMismatches(row, compareOutcomes(ours, *theirs1), true);
            judgeClosest(row, *theirs1);
          });
      add(
          prefix + "intersect8",
          [&peer, &rays, &options, theirs8] { peer.intersect8(rays, options.size, *theirs8); },
          [&, theirs8](BenchRow& row) {
            addMismatches(row, compareOutcomes(ours, *theirs8), true);
            judgeClosest(row, *theirs8);
          });
      add(
          prefix + "intersect16",
          [&peer, &rays, &options, theirs16] { peer.intersect16(rays, options.size, *theirs16); },
          [&, theirs16](BenchRow& row) {
            addMismatches(row, compareOutcomes(ours, *theirs16), true);
            judgeClosest(row, *theirs16);
          });
    }
  }
#endif
  // The other rows compare their answers with the default engine's (`ours`): with its row left
  // out (--rows), they are traced once here, untimed.
  if (!common.timesRow(rows.front().impl)) rows.front().sample();
  measureRows(report, common, reps, rows);
  return report;
}

}  // namespace tg::bench
