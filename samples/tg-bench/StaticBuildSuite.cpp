// The static suite: the build of a whole static scene (flattened into one mesh, as a renderer
// without instancing would hold it) by our high-quality builders and by Embree, each row with
// the trace speed of the structure it built. The target is a build no slower than Embree's
// default (medium) quality at equal or better trace speed.
#include <tbb/task_arena.h>

#include <functional>
#include <list>
#include <vector>

#include "BenchTiming.h"
#include "PrimaryScene.h"
#include "ReferenceJudge.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "Variants.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {

BenchReport runStaticBuildSuite(const CommonOptions& common, const PeerSceneOptions& options) {
  const int buildReps = repsOrDefault(common, kDefaultBuildReps);
  const int traceReps = repsOrDefault(common, kDefaultTraceReps);
  tbb::task_arena arena(common.threads);
  const PrimaryScene primary(options, arena);
  const BenchScene& flat = primary.flat().scene;
  BenchReport report = startReport("static", common);
  const std::string caseName = "static build: " + primary.caseName();
  report.extra.push_back(
      intField("triangles", static_cast<std::int64_t>(flat.instancedTriangleCount())));

  // The row of a build, then the trace of what it built.
  const auto addBuild = [&](const std::string& impl, const TimingSummary& build,
                            const TimingSummary& trace, const std::vector<RayOutcome>& out) {
    BenchRow& row = addRow(report, caseName, impl, build);
    row.extra.push_back(realField("trace_ms", trace.medianMs));
    if (trace.medianMs > 0.0)
      row.mraysPerS = static_cast<double>(out.size()) / (trace.medianMs * 1e3);
    row.extra.push_back(intField("rays", static_cast<std::int64_t>(out.size())));
    primary.judge(row, out, true);
  };

  // Each builder's builds are timed one after the other, each in the memory the previous one
  // freed, before anything else is built: interleaved with other builders (the kd-tree's take
  // hundreds of megabytes), a build also pays for faulting its memory in again, which on this
  // suite's machines costs as much as the build itself and measures the allocator rather than
  // the builder. The structures are then built once more and their traces timed in one
  // interleaved group, so that trace ratios compare the same machine states.
  std::vector<std::string> impls;
  std::vector<TimingSummary> buildTimes;
  std::vector<AccelVariant> variants;
  for (const AccelVariant& v : accelVariants()) {
    if (v.name != "bvh" && v.name != "sah-kd") continue;
    if (!common.timesRow("tracegraph-" + v.name)) continue;
    impls.push_back("tracegraph-" + v.name);
    variants.push_back(v);
    progress("static: " + impls.back());
    // A fresh scene per sample: copying the mesh in is setup, commit() (the object build and a
    // one-instance top level) is measured.
    buildTimes.push_back(measureRepeated(buildReps, [&](int) {
      Scene scene(v.options);
      populateScene(flat, scene);
      return timeMs([&] { arena.execute([&] { scene.commit(); }); });
    }));
  }
#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  std::vector<EmbreeQuality> qualities;
  for (const EmbreeQuality quality : kEmbreeBuildQualities) {
    if (!common.timesRow(embreeImplName(quality))) continue;
    qualities.push_back(quality);
    impls.push_back(embreeImplName(quality));
    progress("static: " + impls.back());
    buildTimes.push_back(timeEmbreeBuilds(device, flat, quality, buildReps));
  }
#endif

  std::vector<std::function<double(int)>> traces;
  std::list<Scene> scenes;
  std::list<std::vector<RayOutcome>> outcomes;  // one per row, at addresses that stay put
  for (const AccelVariant& v : variants) {
    Scene& scene = scenes.emplace_back(v.options);
    populateScene(flat, scene);
    arena.execute([&] { scene.commit(); });
    std::vector<RayOutcome>& out = outcomes.emplace_back(primary.rays().size());
    traces.push_back([&arena, &scene, &out, &primary](int) {
      return timeMs([&] { arena.execute([&] { traceOutcomes(scene, primary.rays(), out); }); });
    });
  }
#ifdef TG_HAVE_EMBREE
  std::list<EmbreeBenchScene> peers;
  for (const EmbreeQuality quality : qualities) {
    EmbreeBenchScene& peer = peers.emplace_back(device, flat, quality);
    arena.execute([&] { peer.commit(); });
    device.check("building the scene");
    std::vector<RayOutcome>& out = outcomes.emplace_back(primary.rays().size());
    traces.push_back([&arena, &peer, &out, &primary](int) {
      return timeMs([&] { arena.execute([&] { peer.intersect1(primary.rays(), out); }); });
    });
  }
#endif
  if (impls.empty()) {
    progress("static: --rows names none of this suite's rows");
    return report;
  }
  progress("static: " + std::to_string(traceReps) + " interleaved rounds of traces");
  const std::vector<TimingSummary> traceTimes = measureInterleaved(traceReps, traces);
  auto out = outcomes.begin();
  for (std::size_t i = 0; i < impls.size(); ++i, ++out)
    addBuild(impls[i], buildTimes[i], traceTimes[i], *out);

#ifdef TG_HAVE_EMBREE
  addTimeRatios(report, embreeImplName(EmbreeQuality::Medium), "build_vs_embree_medium");
  addThroughputRatios(report, embreeImplName(EmbreeQuality::Medium), "trace_vs_embree_medium");
#endif
  return report;
}

}  // namespace tg::bench
