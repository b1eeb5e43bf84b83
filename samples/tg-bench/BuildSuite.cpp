// The build suite: building every object of a scene plus its top level from scratch, the
// load-time cost of a static scene.
#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/Scene.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {
namespace {

void describeScene(BenchRow& row, const BenchScene& scene) {
  std::size_t triangles = 0;
  for (const TriangleMesh& mesh : scene.meshes) triangles += mesh.triangleCount();
  row.extra.push_back(intField("objects", static_cast<std::int64_t>(scene.meshes.size())));
  row.extra.push_back(intField("instances", static_cast<std::int64_t>(scene.instances.size())));
  row.extra.push_back(intField("triangles", static_cast<std::int64_t>(triangles)));
  row.extra.push_back(
      intField("instanced_triangles", static_cast<std::int64_t>(scene.instancedTriangleCount())));
}

}  // namespace

BenchReport runBuildSuite(const CommonOptions& common, const BuildOptions& options) {
  const int reps = repsOrDefault(common, kDefaultBuildReps);
  const BenchScene scene = loadBenchScene(options.scene);
  BenchReport report = startReport("build", common);
  const std::string& caseName = options.scene;

  progress("build: tracegraph-sah-kd");
  {
    // A fresh Scene per sample; copying the meshes into it is setup, commit() (all objects
    // built in parallel with the SAH builder, then the top level) is measured.
    const TimingSummary t = measureRepeated(reps, [&](int) {
      Scene ours;
      populateScene(scene, ours);
      return timeMs([&] { ours.commit(); });
    });
    describeScene(addRow(report, caseName, "tracegraph-sah-kd", t), scene);
  }

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads);
  for (const EmbreeQuality quality : kEmbreeBuildQualities) {
    progress("build: " + embreeImplName(quality));
    const TimingSummary t = measureRepeated(reps, [&](int) {
      EmbreeBenchScene peer(device, scene, quality);
      const double ms = timeMs([&] { peer.commit(); });
      device.check("committing the scene");
      return ms;
    });
    addRow(report, caseName, embreeImplName(quality), t);
  }
#endif
  return report;
}

}  // namespace tg::bench
