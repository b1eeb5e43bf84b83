// The build suite: building every object of a scene plus its top level from scratch, the
// load-time cost of a static scene.
#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "ReferenceJudge.h"
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

  // The structures timed below are judged afterwards on the same probe rays against the
  // double-precision reference, so that every build time comes with its error.
  Scene judged;
  populateScene(scene, judged);
  judged.commit();
  const ReferenceIntersector reference(judged);
  const std::vector<Ray> probes = makeProbeRays(judged.bounds(), kProbeRays, 99);
  const std::vector<ReferenceHit> expected = referenceHits(reference, probes);
  const auto addJudgement = [](BenchRow& row, const Judgement& j) {
    row.extra.push_back(intField("ref_mismatches", static_cast<std::int64_t>(j.mismatches)));
    row.extra.push_back(intField("judged", static_cast<std::int64_t>(j.rays)));
  };

  progress("build: tracegraph-sah-kd");
  {
    // A fresh Scene per sample; copying the meshes into it is setup, commit() (all objects
    // built in parallel with the SAH builder, then the top level) is measured.
    const TimingSummary t = measureRepeated(reps, [&](int) {
      Scene ours;
      populateScene(scene, ours);
      return timeMs([&] { ours.commit(); });
    });
    BenchRow& row = addRow(report, caseName, "tracegraph-sah-kd", t);
    describeScene(row, scene);
    addJudgement(row, judgeOutcomes(expected, traceOutcomes(judged, probes)));
  }

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  for (const EmbreeQuality quality : kEmbreeBuildQualities) {
    progress("build: " + embreeImplName(quality));
    const TimingSummary t = timeEmbreeBuilds(device, scene, quality, reps);
    EmbreeBenchScene peer(device, scene, quality);
    peer.commit();
    std::vector<RayOutcome> out(probes.size());
    peer.intersect1(probes, out);
    addJudgement(addRow(report, caseName, embreeImplName(quality), t),
                 judgeOutcomes(expected, out));
  }
#endif
  return report;
}

}  // namespace tg::bench
