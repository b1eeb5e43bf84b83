// The overhead suite: what the two levels cost a ray. The same primary rays are traced through
// the scene as the scene graph instances it and through the same triangles flattened into one
// object, per engine and for Embree; the ratio of the two times is the two-level overhead.
#include <tbb/task_arena.h>

#include <functional>
#include <list>
#include <memory>

#include "BenchTiming.h"
#include "PrimaryScene.h"
#include "ReferenceJudge.h"
#include "SuiteCommon.h"
#include "Suites.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {

BenchReport runOverheadSuite(const CommonOptions& common, const PeerSceneOptions& options) {
  const int reps = repsOrDefault(common, kDefaultTraceReps);
  tbb::task_arena arena(common.threads);
  const PrimaryScene primary(options, arena);
  BenchReport report = startReport("overhead", common);
  const std::string caseName = "two-level overhead: " + primary.caseName();
  report.extra.push_back(
      intField("instances", static_cast<std::int64_t>(primary.bench().instances.size())));
  report.extra.push_back(
      intField("objects", static_cast<std::int64_t>(primary.bench().meshes.size())));

  struct Layout {
    const BenchScene* scene;
    const char* name;
    bool flattened;
  };
  const Layout layouts[] = {{&primary.bench(), "instanced", false},
                            {&primary.flat().scene, "flattened", true}};
  // Every structure is built first, then all are timed in one interleaved group: the ratios
  // this suite reports are between its rows.
  std::vector<TimedRow> rows;
  std::vector<std::unique_ptr<Scene>> scenes;
  std::list<std::vector<RayOutcome>> outcomes;  // one per row, at addresses that stay put
  const auto add = [&](const std::string& impl, const Layout& layout,
                       std::function<void(std::vector<RayOutcome>&)> trace) {
    std::vector<RayOutcome>& out = outcomes.emplace_back(primary.rays().size());
    rows.push_back({caseName, impl + " " + layout.name,
                    [&arena, &out, trace = std::move(trace)] {
                      return timeMs([&] { arena.execute([&] { trace(out); }); });
                    },
                    [&primary, &out, flattened = layout.flattened](BenchRow& row) {
                      setRays(row, out.size());
                      primary.judge(row, out, flattened);
                    }});
  };
  for (const Engine engine : {Engine::Bvh, Engine::KdTree}) {
    const std::string impl = engine == Engine::Bvh ? "tracegraph-bvh" : "tracegraph-kd";
    for (const Layout& layout : layouts) {
      progress("overhead: building " + impl + " " + layout.name);
      Scene& scene = *scenes.emplace_back(std::make_unique<Scene>(sceneOptionsFor(engine)));
      populateScene(*layout.scene, scene);
      arena.execute([&] { scene.commit(); });
      add(impl, layout, [&primary, &scene](std::vector<RayOutcome>& out) {
        traceOutcomes(scene, primary.rays(), out);
      });
    }
  }

#ifdef TG_HAVE_EMBREE
  // Static scenes at the quality Tracegraph's static objects get (SAH), as in the trace suite.
  EmbreeDevice device(common.threads, common.embreeConfig);
  const std::string peer = embreeImplName(EmbreeQuality::High);
  std::vector<std::unique_ptr<EmbreeBenchScene>> peers;
  for (const Layout& layout : layouts) {
    progress("overhead: building " + peer + " " + layout.name);
    EmbreeBenchScene& scene = *peers.emplace_back(
        std::make_unique<EmbreeBenchScene>(device, *layout.scene, EmbreeQuality::High));
    arena.execute([&] { scene.commit(); });
    device.check("building the scene");
    add(peer, layout, [&primary, &scene](std::vector<RayOutcome>& out) {
      scene.intersect1(primary.rays(), out);
    });
  }
#endif
  measureRows(report, common, reps, rows);

#ifdef TG_HAVE_EMBREE
  // Ours against Embree in the same layout ("<impl> instanced" against "embree-high instanced").
  addTimeRatios(
      report,
      [&](const BenchRow& row) {
        return row.impl.rfind("tracegraph", 0) == 0 ? peer + row.impl.substr(row.impl.find(' '))
                                                    : std::string();
      },
      "time_vs_embree");
#endif
  constexpr std::string_view kInstanced = " instanced";
  addTimeRatios(
      report,
      [&](const BenchRow& row) {
        return row.impl.ends_with(kInstanced)
                   ? row.impl.substr(0, row.impl.size() - kInstanced.size()) + " flattened"
                   : std::string();
      },
      "instanced_over_flattened");
  return report;
}

}  // namespace tg::bench
