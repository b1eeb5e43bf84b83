// The static suite: the build of a whole static scene (flattened into one mesh, as a renderer
// without instancing would hold it) by our high-quality builders and by Embree, each row with
// the trace speed of the structure it built. The target is a build no slower than Embree's
// default (medium) quality at equal or better trace speed.
#include <tbb/task_arena.h>

#include "BenchTiming.h"
#include "PrimaryScene.h"
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

  for (const AccelVariant& v : accelVariants()) {
    if (v.name != "bvh" && v.name != "sah-kd") continue;
    progress("static: tracegraph-" + v.name);
    // A fresh scene per sample: copying the mesh in is setup, commit() (the object build and a
    // one-instance top level) is measured.
    const TimingSummary build = measureRepeated(buildReps, [&](int) {
      Scene scene(v.options);
      populateScene(flat, scene);
      return timeMs([&] { arena.execute([&] { scene.commit(); }); });
    });
    Scene scene(v.options);
    populateScene(flat, scene);
    arena.execute([&] { scene.commit(); });
    std::vector<RayOutcome> out;
    const TimingSummary trace = timeTrace(arena, traceReps, scene, primary.rays(), out);
    addBuild("tracegraph-" + v.name, build, trace, out);
  }

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads);
  for (const EmbreeQuality quality : kEmbreeBuildQualities) {
    progress("static: " + embreeImplName(quality));
    const TimingSummary build = timeEmbreeBuilds(device, flat, quality, buildReps);
    EmbreeBenchScene peer(device, flat, quality);
    arena.execute([&] { peer.commit(); });
    std::vector<RayOutcome> out;
    const TimingSummary trace = timeTrace(arena, traceReps, peer, primary.rays(), out);
    addBuild(embreeImplName(quality), build, trace, out);
  }
  addTimeRatios(report, embreeImplName(EmbreeQuality::Medium), "build_vs_embree_medium");
  addThroughputRatios(report, embreeImplName(EmbreeQuality::Medium), "trace_vs_embree_medium");
#endif
  return report;
}

}  // namespace tg::bench
