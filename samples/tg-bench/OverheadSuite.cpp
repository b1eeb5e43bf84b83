// The overhead suite: what the two levels cost a ray. The same primary rays are traced through
// the scene as the scene graph instances it and through the same triangles flattened into one
// object, per engine and for Embree; the ratio of the two times is the two-level overhead.
#include <tbb/task_arena.h>

#include "BenchTiming.h"
#include "PrimaryScene.h"
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
  std::vector<RayOutcome> out;
  for (const Engine engine : {Engine::Bvh, Engine::KdTree}) {
    const std::string impl = engine == Engine::Bvh ? "tracegraph-bvh" : "tracegraph-kd";
    for (const Layout& layout : layouts) {
      progress("overhead: " + impl + " " + layout.name);
      Scene scene(sceneOptionsFor(engine));
      populateScene(*layout.scene, scene);
      arena.execute([&] { scene.commit(); });
      BenchRow& row = addRow(report, caseName, impl + " " + layout.name,
                             timeTrace(arena, reps, scene, primary.rays(), out));
      setRays(row, out.size());
      primary.judge(row, out, layout.flattened);
    }
  }

#ifdef TG_HAVE_EMBREE
  // Static scenes at the quality Tracegraph's static objects get (SAH), as in the trace suite.
  EmbreeDevice device(common.threads);
  const std::string peer = embreeImplName(EmbreeQuality::High);
  for (const Layout& layout : layouts) {
    progress("overhead: " + peer + " " + layout.name);
    EmbreeBenchScene scene(device, *layout.scene, EmbreeQuality::High);
    arena.execute([&] { scene.commit(); });
    device.check("building the scene");
    BenchRow& row = addRow(report, caseName, peer + " " + layout.name,
                           timeTrace(arena, reps, scene, primary.rays(), out));
    setRays(row, out.size());
    primary.judge(row, out, layout.flattened);
  }
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
