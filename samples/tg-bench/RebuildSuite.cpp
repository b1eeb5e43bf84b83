// The rebuild suite: a from-scratch build over a moving triangle soup, the per-frame cost of a
// deforming object (the paper's fast kd-tree builder) against Embree's builders and refit.
#include <memory>
#include <vector>

#include "BenchTiming.h"
#include "ReferenceJudge.h"
#include "SceneGenerators.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/KdTreeAccel.h"
#include "tracegraph/backend/Scene.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {

BenchReport runRebuildSuite(const CommonOptions& common, const RebuildOptions& options) {
  const int reps = repsOrDefault(common, kDefaultBuildReps);
  const std::size_t n = options.triangles;
  BenchReport report = startReport("rebuild", common);
  const std::string caseName = std::to_string(n) + " triangles";

  const TriangleMesh base = makeRandomTriangles(n, 0x5EED0002u);
  // Each frame moves every point by up to a twentieth of a triangle edge: small enough that a
  // refit stays reasonable, which is the case refitting is designed for.
  constexpr float kMotion = 0.05f;
  TriangleMesh moving = base;
  const auto moveTo = [&](int frame) {
    perturbPositions(base.positions, kMotion, 2000 + static_cast<std::uint64_t>(frame),
                     moving.positions);
  };

  // The deforming builders first (the fast kd-tree keeps the first row, as before), then the
  // high-quality ones; "-refit" rows time ObjectAccel::refit of the same motion.
  struct Variant {
    AccelKind kind;
    bool refit;
  };
  for (const Variant v : {Variant{AccelKind::FastKdTree, false}, Variant{AccelKind::BvhFast, false},
                          Variant{AccelKind::BvhFast, true}, Variant{AccelKind::SahKdTree, false},
                          Variant{AccelKind::Bvh, false}}) {
    const AccelKind kind = v.kind;
    const std::string impl =
        "tracegraph-" + std::string(accelKindName(kind)) + (v.refit ? "-refit" : "");
    progress("rebuild: " + impl);
    // ObjectAccel::build is what Scene::commit() runs for a changed object: it includes
    // gathering the triangles out of the indexed mesh.
    const std::unique_ptr<ObjectAccel> built = createObjectAccel(kind);
    ObjectAccel& accel = *built;
    if (v.refit) accel.build(base);
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      moveTo(k);
      if (v.refit) return timeMs([&] { accel.refit(moving); });
      return timeMs([&] { accel.build(moving); });
    });
    BenchRow& row = addRow(report, caseName, impl, t);
    const BuildStats& s = accel.stats();
    row.extra.push_back(intField("nodes", static_cast<std::int64_t>(s.nodes)));
    row.extra.push_back(intField("leaves", static_cast<std::int64_t>(s.leaves)));
    row.extra.push_back(intField("max_depth", static_cast<std::int64_t>(s.maxDepth)));
    row.extra.push_back(intField("prim_refs", static_cast<std::int64_t>(s.primReferences)));
    if (v.refit) row.extra.push_back(intField("refitted", s.refitted ? 1 : 0));
    // The last frame's mesh built by the same builder, judged against the reference.
    const bool kd = kind == AccelKind::FastKdTree || kind == AccelKind::SahKdTree;
    SceneOptions sceneOptions = sceneOptionsFor(kd ? Engine::KdTree : Engine::Bvh);
    sceneOptions.deformingAccel = kind;
    Scene scene(sceneOptions);
    scene.createInstance(scene.createObject(moving, ObjectUsage::Deforming));
    scene.commit();
    const Judgement j = probeScene(scene);
    row.extra.push_back(intField("ref_mismatches", static_cast<std::int64_t>(j.mismatches)));
    row.extra.push_back(intField("judged", static_cast<std::int64_t>(j.rays)));
  }

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  for (const EmbreeQuality quality :
       {EmbreeQuality::Low, EmbreeQuality::Medium, EmbreeQuality::High, EmbreeQuality::Refit}) {
    progress("rebuild: " + embreeImplName(quality));
    // The warm-up sample performs the initial build, so the refit row times refits only.
    EmbreeDeformingMesh peer(device, base, quality);
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      moveTo(k);
      peer.setPositions(moving.positions);
      return timeMs([&] { peer.commit(); });
    });
    device.check("committing the deforming mesh");
    addRow(report, caseName, embreeImplName(quality), t);
  }
#endif
  return report;
}

}  // namespace tg::bench
