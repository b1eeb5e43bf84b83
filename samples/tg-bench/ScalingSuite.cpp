// The scaling suite: primary-ray throughput on one thread and on all the threads the run may
// use, per engine and for Embree, traced by the same parallel loop in task arenas of each
// size. Tracing is read-only, so the speedup shows what shared memory bandwidth and the
// scheduler leave of linear scaling.
#include <tbb/task_arena.h>

#include <functional>
#include <list>
#include <map>
#include <memory>
#include <optional>

#include "BenchTiming.h"
#include "PrimaryScene.h"
#include "ReferenceJudge.h"
#include "SuiteCommon.h"
#include "Suites.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {

BenchReport runScalingSuite(const CommonOptions& common, const PeerSceneOptions& options) {
  const int reps = repsOrDefault(common, kDefaultTraceReps);
  tbb::task_arena all(common.threads);
  const PrimaryScene primary(options, all);
  BenchReport report = startReport("scaling", common);
  std::vector<int> threadCounts = {1};
  if (common.threads > 1)
    threadCounts.push_back(common.threads);
  else
    progress("scaling: --threads 1 leaves nothing to compare; only 1-thread rows");

  // Every structure is built once, with all threads; only the traces run in smaller arenas.
  struct Traced {
    std::string impl;
    /// One trace of the rays inside the arena.
    std::function<void(tbb::task_arena&, std::vector<RayOutcome>&)> trace;
  };
  std::vector<Traced> traced;
  std::vector<std::unique_ptr<Scene>> scenes;
  for (const Engine engine : {Engine::Bvh, Engine::KdTree}) {
    scenes.push_back(std::make_unique<Scene>(sceneOptionsFor(engine)));
    Scene& scene = *scenes.back();
    populateScene(primary.bench(), scene);
    all.execute([&] { scene.commit(); });
    traced.push_back({engine == Engine::Bvh ? "tracegraph-bvh" : "tracegraph-kd",
                      [&, s = &scene](tbb::task_arena& arena, std::vector<RayOutcome>& out) {
                        arena.execute([&] { traceOutcomes(*s, primary.rays(), out); });
                      }});
  }
#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  EmbreeBenchScene peer(device, primary.bench(), EmbreeQuality::High);
  all.execute([&] { peer.commit(); });
  device.check("building the scene");
  traced.push_back({"embree-intersect1", [&](tbb::task_arena& arena, std::vector<RayOutcome>& out) {
                      arena.execute([&] { peer.intersect1(primary.rays(), out); });
                    }});
#endif

  // Every thread count and implementation in one interleaved group: the speedup is a ratio of
  // two rows, which then see the same machine states.
  std::list<tbb::task_arena> arenas;
  std::list<std::vector<RayOutcome>> outcomes;
  std::vector<TimedRow> rows;
  for (const int threads : threadCounts) {
    tbb::task_arena& arena = arenas.emplace_back(threads);
    const std::string caseName = "thread scaling: " + primary.caseName() + ", " +
                                 std::to_string(threads) + (threads == 1 ? " thread" : " threads");
    for (const Traced& t : traced) {
      std::vector<RayOutcome>& out = outcomes.emplace_back(primary.rays().size());
      rows.push_back({caseName, t.impl,
                      [&arena, &out, &t] { return timeMs([&] { t.trace(arena, out); }); },
                      [&primary, &out, threads](BenchRow& row) {
                        setRays(row, out.size());
                        row.extra.push_back(intField("trace_threads", threads));
                        primary.judge(row, out, false);
                      }});
    }
  }
  measureRows(report, common, reps, rows);
  std::map<std::string, double> oneThreadMs;
  for (BenchRow& row : report.rows) {
    const bool oneThread = row.caseName.ends_with(", 1 thread");
    if (oneThread)
      oneThreadMs[row.impl] = row.timing.medianMs;
    else if (row.timing.medianMs > 0.0)
      row.extra.push_back(realField("speedup", oneThreadMs[row.impl] / row.timing.medianMs));
  }
  // Our speedup against the peer's, both measured in this run.
  const auto speedupOf = [](const BenchRow& row) -> std::optional<double> {
    for (const ExtraField& f : row.extra)
      if (f.key == "speedup") return std::get<double>(f.value);
    return std::nullopt;
  };
  std::optional<double> peerSpeedup;
  for (const BenchRow& row : report.rows)
    if (row.impl == "embree-intersect1" && speedupOf(row)) peerSpeedup = speedupOf(row);
  for (BenchRow& row : report.rows) {
    const std::optional<double> ours = speedupOf(row);
    if (row.impl.rfind("tracegraph", 0) == 0 && ours && peerSpeedup && *peerSpeedup > 0.0)
      row.extra.push_back(realField("speedup_vs_embree", *ours / *peerSpeedup));
  }
  return report;
}

}  // namespace tg::bench
