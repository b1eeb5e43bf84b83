// The toplevel suite: how long rebuilding the top-level structure takes when every instance
// moved, the per-frame cost the paper's design rests on (Wald et al. 2003 rebuild the top
// level from scratch every frame).
#include <cmath>
#include <vector>

#include "BenchTiming.h"
#include "ReferenceJudge.h"
#include "SceneGenerators.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/KdTreeAccel.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/TopLevelKdTree.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {
namespace {

/// What Scene::commit() derives from an instance before the top-level build: the inverse
/// matrix and the world bounds of the object's box.
void fillRecords(const ObjectAccel& accel, std::span<const Affine3d> placements,
                 std::vector<InstanceRecord>& records) {
  const Box3f b = accel.bounds();
  const Box3d objectBounds(Vec3d(b.lower), Vec3d(b.upper));
  records.resize(placements.size());
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const Affine3d& m = placements[i];
    const Box3d world = m.transformBox(objectBounds);
    InstanceRecord& r = records[i];
    r.accel = &accel;
    r.worldToObjectD = m.inverse().value();
    r.worldBounds = Box3f(Vec3f(world.lower), Vec3f(world.upper));
    r.instanceId = static_cast<std::uint32_t>(i);
    r.objectId = 0;
    r.identity = false;
  }
}

void addTopLevelStats(BenchRow& row, const TopLevelStats& s) {
  row.extra.push_back(intField("nodes", static_cast<std::int64_t>(s.nodes)));
  row.extra.push_back(intField("leaves", static_cast<std::int64_t>(s.leaves)));
  row.extra.push_back(intField("max_depth", static_cast<std::int64_t>(s.maxDepth)));
  row.extra.push_back(intField("references", static_cast<std::int64_t>(s.references)));
}

}  // namespace

BenchReport runToplevelSuite(const CommonOptions& common, const ToplevelOptions& options) {
  const int reps = repsOrDefault(common, kDefaultBuildReps);
  const std::size_t n = options.instances;
  BenchReport report = startReport("toplevel", common);
  const std::string caseName = std::to_string(n) + " instances";

  // A 12-triangle box, deliberately not a cube so that rotations change its world bounds.
  const TriangleMesh box = makeBoxMesh(Vec3f(0.5f, 0.25f, 0.125f));
  // About 8 units of volume per instance: instances are scattered, with some overlap.
  const double side = 2.0 * std::cbrt(static_cast<double>(n));
  // One frame of placements per sample (warm-up included), the same sequence for every
  // implementation.
  std::vector<std::vector<Affine3d>> frames;
  for (int k = 0; k <= reps; ++k)
    frames.push_back(makeRandomPlacements(n, side, 1000 + static_cast<std::uint64_t>(k)));

  for (const Engine engine : {Engine::KdTree, Engine::Bvh}) {
    const std::string impl = engine == Engine::KdTree ? "tracegraph-kd" : "tracegraph-bvh";
    progress("toplevel: " + impl);
    // Through the public API: move every instance, commit, and take the top-level part of the
    // commit (instance records with world bounds, then Algorithm 1 or the BVH build); no
    // object is rebuilt.
    Scene scene(sceneOptionsFor(engine));
    const ObjectId object = scene.createObject(box, ObjectUsage::Rigid);
    for (const Affine3d& m : frames[0]) scene.createInstance(object, m);
    scene.commit();
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      const std::vector<Affine3d>& frame = frames[static_cast<std::size_t>(k)];
      for (std::size_t i = 0; i < n; ++i)
        scene.setInstanceTransform(static_cast<InstanceId>(i), frame[i]);
      return scene.commit().topLevelMs;
    });
    BenchRow& row = addRow(report, caseName, impl, t);
    addTopLevelStats(row, scene.topLevel().stats());
    // The last frame's two-level structure against the reference (Embree's instance scenes
    // here are built, never traced, so they carry no such figure).
    const Judgement j = probeScene(scene);
    row.extra.push_back(intField("ref_mismatches", static_cast<std::int64_t>(j.mismatches)));
    row.extra.push_back(intField("judged", static_cast<std::int64_t>(j.rays)));
  }

  for (const TopLevelKind kind : {TopLevelKind::KdTree, TopLevelKind::Bvh}) {
    const std::string impl = "tracegraph-" + std::string(topLevelKindName(kind)) + "-build";
    progress("toplevel: " + impl);
    // The top-level builder alone, over records prepared outside the measurement.
    KdTreeAccel accel(AccelKind::SahKdTree);
    accel.build(box);
    std::vector<InstanceRecord> records;
    const std::unique_ptr<TopLevelAccel> tree = createTopLevelAccel(kind);
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      fillRecords(accel, frames[static_cast<std::size_t>(k)], records);
      return timeMs([&] { tree->build(records); });
    });
    addTopLevelStats(addRow(report, caseName, impl, t), tree->stats());
  }

#ifdef TG_HAVE_EMBREE
  EmbreeDevice device(common.threads, common.embreeConfig);
  for (const EmbreeQuality quality :
       {EmbreeQuality::Low, EmbreeQuality::Medium, EmbreeQuality::High, EmbreeQuality::Refit}) {
    progress("toplevel: " + embreeImplName(quality));
    EmbreeInstanceScene peer(device, box, n, quality);
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      peer.setTransforms(frames[static_cast<std::size_t>(k)]);
      return timeMs([&] { peer.commit(); });
    });
    device.check("committing the instance scene");
    addRow(report, caseName, embreeImplName(quality), t);
  }
  // Every row of ours against Embree's default build quality, measured above.
  addTimeRatios(report, embreeImplName(EmbreeQuality::Medium), "vs_embree_medium");
#endif
  return report;
}

}  // namespace tg::bench
