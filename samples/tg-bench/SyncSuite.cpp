// The sync suite: what keeping the backend scene equal to the scene graph costs.
//
// Edit cases (issue "Scene graph"): one field edit in graphs of 10^3 .. 10^5 nodes, timed as
// the SceneGraph::sync() that follows it. The target is at most 50 us at 10^5 nodes excluding
// the top-level rebuild, which is why every row also reports sync minus top level: the graph
// side of the sync must follow the number of changes, not the size of the graph, while the
// top-level rebuild follows the number of instances and is measured by the toplevel suite.
//
// Frame case: one whole animation frame of a scene (BART robots, or the built-in demo) --
// animators, sync, object rebuilds, top level -- against what a renderer without a two-level
// structure pays: flattening every instance to world space and rebuilding one Embree LOW
// structure over all of it, every frame.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "BenchTiming.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/Transform.h"
#include "tracegraph/scenegraph/SceneGraph.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreeFlatScene.h"
#endif

namespace tg::bench {
namespace {

using nodes::Mesh;
using nodes::OrientationInterpolator;
using nodes::Separator;
using nodes::Transform;

/// Frame rate for scenes without their own frame range (the demo), as tg-render's default.
constexpr double kFps = 30.0;

// Shape of the synthetic graphs: a balanced tree whose leaves are parts Separator { Transform,
// Mesh } and whose inner levels are Separator { Transform, up to kFanOut children }.
constexpr std::size_t kFanOut = 8;
constexpr std::size_t kNodesPerLeaf = 3;
constexpr std::size_t kNodesPerGroup = 2;
// One leaf in 16 has a driven transform (a rigid instance of its own), and one first-level
// group in 32 has one (a rigid object of 8 parts moving together): a mostly static world with
// moving parts at two levels, as in the BART scenes.
constexpr std::size_t kDynamicLeafEvery = 16;
constexpr std::size_t kDynamicLeafPhase = 8;
constexpr std::size_t kDynamicGroupEvery = 32;
constexpr std::size_t kDynamicGroupPhase = 16;

/// Nodes of a tree over `leaves` parts (animators are outside the graph and not counted).
std::size_t treeNodes(std::size_t leaves) {
  std::size_t total = kNodesPerLeaf * leaves;
  for (std::size_t count = leaves; count > 1;) {
    count = (count + kFanOut - 1) / kFanOut;
    total += kNodesPerGroup * count;
  }
  return total;
}

/// The most leaves whose tree has at most `target` nodes (at least one).
std::size_t leavesFor(std::size_t target) {
  std::size_t lo = 1, hi = std::max<std::size_t>(1, target / kNodesPerLeaf);
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (treeNodes(mid) <= target) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

bool dynamicLeaf(std::size_t leaf) {
  return leaf % kDynamicLeafEvery == kDynamicLeafPhase;
}
bool dynamicGroup(std::size_t group) {
  return group % kDynamicGroupEvery == kDynamicGroupPhase;
}

/// A 12-triangle box of half-size `h` about the origin. Every part gets its own Mesh node: a
/// shared one would make all parts instances of one object, a different (and rarer) case.
ref_ptr<Mesh> boxMesh(float h) {
  std::vector<Vec3f> p;
  for (int i = 0; i < 8; ++i) p.push_back({(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h});
  std::vector<std::int32_t> idx = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return Mesh::create(std::move(p), std::move(idx));
}

/// A synthetic graph and the handles the edit cases need.
struct SyntheticGraph {
  ref_ptr<Node> root;
  std::size_t nodes = 0;
  std::size_t triangles = 0;
  /// Drives the dynamic transforms (never evaluated: being connected is what makes them
  /// dynamic, and the edits below are the only changes).
  ref_ptr<OrientationInterpolator> driver;
  ref_ptr<Transform> dynamicEdit;  ///< a driven leaf transform, in the middle of the tree
  std::vector<ref_ptr<Transform>> staticLeaves;  ///< static leaves outside moving groups
};

SyntheticGraph makeSyntheticGraph(std::size_t targetNodes) {
  SyntheticGraph g;
  const std::size_t leaves = leavesFor(targetNodes);
  g.nodes = treeNodes(leaves);
  g.driver = OrientationInterpolator::create();
  g.driver->key = std::vector<float>{0.0f, 1.0f};
  g.driver->keyValue =
      std::vector<Rotation>{Rotation{{0.0f, 1.0f, 0.0f}, 0.0f}, Rotation{{0.0f, 1.0f, 0.0f}, 1.0f}};

  // Leaves on a cubic grid of unit cells in index order, so that the parts of a group are
  // neighbours and every group occupies a compact region.
  const auto side =
      static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(leaves)) - 1e-9));
  std::vector<ref_ptr<Node>> level;
  level.reserve(leaves);
  std::size_t middleDistance = leaves;
  for (std::size_t i = 0; i < leaves; ++i) {
    ref_ptr<Separator> part = Separator::create();
    ref_ptr<Transform> xf = Transform::create();
    xf->translation = Vec3f(static_cast<float>(i % side), static_cast<float>(i / side % side),
                            static_cast<float>(i / (side * side)));
    const bool movingGroup = dynamicGroup(i / kFanOut);
    if (dynamicLeaf(i)) {
      xf->rotation.connectFrom(g.driver->value_changed);
      const std::size_t distance = i > leaves / 2 ? i - leaves / 2 : leaves / 2 - i;
      if (!movingGroup && distance < middleDistance) {
        middleDistance = distance;
        g.dynamicEdit = xf;
      }
    } else if (!movingGroup) {
      g.staticLeaves.push_back(xf);
    }
    part->addChild(xf);
    part->addChild(boxMesh(0.3f));
    g.triangles += 12;
    level.push_back(part);
  }
  for (int depth = 1; level.size() > 1; ++depth) {
    std::vector<ref_ptr<Node>> next;
    next.reserve((level.size() + kFanOut - 1) / kFanOut);
    for (std::size_t j = 0; j * kFanOut < level.size(); ++j) {
      ref_ptr<Separator> group = Separator::create();
      ref_ptr<Transform> xf = Transform::create();
      if (depth == 1 && dynamicGroup(j)) xf->rotation.connectFrom(g.driver->value_changed);
      group->addChild(xf);
      const std::size_t end = std::min(level.size(), (j + 1) * kFanOut);
      for (std::size_t c = j * kFanOut; c < end; ++c) group->addChild(level[c]);
      next.push_back(group);
    }
    level = std::move(next);
  }
  g.root = level.front();
  return g;
}

double median(std::vector<double> values) {
  return summarize(std::move(values)).medianMs;
}

/// What the samples of one edit case collected besides the sync time.
struct EditSamples {
  std::vector<double> editMs, syncMinusTopLevelMs, topLevelMs, rebuildMs;
  std::vector<double> reclassifyMs;
  FrameStats last;
  SyncDebugStats debug;

  void add(double edit, const FrameStats& stats, const SyncDebugStats& d) {
    editMs.push_back(edit);
    syncMinusTopLevelMs.push_back(stats.syncMs - stats.toplevelMs);
    topLevelMs.push_back(stats.toplevelMs);
    rebuildMs.push_back(stats.rebuildMs);
    reclassifyMs.push_back(d.reclassifyMs);
    last = stats;
    debug = d;
  }

  void addTo(BenchRow& row) const {
    row.extra.push_back(realField("sync_minus_toplevel_ms", median(syncMinusTopLevelMs)));
    row.extra.push_back(realField("toplevel_ms", median(topLevelMs)));
    row.extra.push_back(realField("rebuild_ms", median(rebuildMs)));
    row.extra.push_back(realField("reclassify_ms", median(reclassifyMs)));
    row.extra.push_back(realField("edit_ms", median(editMs)));
    row.extra.push_back(intField("instances", static_cast<std::int64_t>(last.instances)));
    row.extra.push_back(
        intField("objects_rebuilt", static_cast<std::int64_t>(last.objectsRebuilt)));
    row.extra.push_back(
        intField("triangles_rebuilt", static_cast<std::int64_t>(last.trianglesRebuilt)));
    row.extra.push_back(intField("reclassified", static_cast<std::int64_t>(last.reclassified)));
    row.extra.push_back(intField("dirty_nodes", static_cast<std::int64_t>(debug.dirtyNodes)));
    row.extra.push_back(intField("nodes_visited", static_cast<std::int64_t>(debug.nodesVisited)));
    row.extra.push_back(intField("frames_updated", static_cast<std::int64_t>(debug.framesUpdated)));
    row.extra.push_back(intField("chunks_rebuilt", static_cast<std::int64_t>(debug.chunksRebuilt)));
  }
};

void runEditCases(BenchReport& report, std::size_t targetNodes, int reps) {
  const std::string size = std::to_string(targetNodes) + " nodes";
  progress("sync: building a graph of " + size);
  const SyntheticGraph g = makeSyntheticGraph(targetNodes);

  // A static transform edited once is promoted at once and demoted after its rest period;
  // the period is stretched past the end of the run so that every static-edit sample is
  // exactly one promotion and no sample also pays for an earlier part going back to rest.
  SyncOptions syncOptions;
  syncOptions.restFrames =
      std::max<std::uint32_t>(syncOptions.restFrames, 4 * static_cast<std::uint32_t>(reps) + 16);
  SceneGraph graph(syncOptions);
  graph.setRoot(g.root);
  FrameStats first;
  const double firstMs = timeMs([&] { first = graph.sync(); });

  auto addCommon = [&](BenchRow& row) {
    row.extra.push_back(intField("nodes", static_cast<std::int64_t>(g.nodes)));
    row.extra.push_back(intField("triangles", static_cast<std::int64_t>(g.triangles)));
  };

  if (g.dynamicEdit) {
    progress("sync: " + size + ", dynamic edit");
    const Vec3f base = g.dynamicEdit->translation.getValue();
    EditSamples samples;
    const TimingSummary t = measureRepeated(reps, [&](int k) {
      // A new value every sample (an equal one would not notify).
      const Vec3f moved = base + Vec3f(0.01f * static_cast<float>(k + 1), 0.0f, 0.0f);
      const double editMs = timeMs([&] { g.dynamicEdit->translation = moved; });
      FrameStats stats;
      const double ms = timeMs([&] { stats = graph.sync(); });
      if (k > 0) samples.add(editMs, stats, graph.debugStats());
      return ms;
    });
    BenchRow& row = addRow(report, size + ", dynamic edit", "tracegraph-sync", t);
    addCommon(row);
    samples.addTo(row);
    row.extra.push_back(realField("first_sync_ms", firstMs));
  } else {
    progress("sync: " + size + ": too few leaves for a dynamic transform, no dynamic-edit row");
  }

  if (g.staticLeaves.size() < 2) {
    progress("sync: " + size + ": too few static transforms, no static-edit row");
  } else {
    // Each sample edits a static transform never edited before, spread over the tree (and so
    // over the static chunks): the edit promotes its part to a rigid instance of its own,
    // re-traverses its region and rebuilds the chunk it leaves.
    const std::size_t available = g.staticLeaves.size();
    int staticReps = reps;
    if (static_cast<std::size_t>(staticReps) + 1 > available) {
      staticReps = static_cast<int>(available) - 1;
      progress("sync: " + size + ": only " + std::to_string(available) +
               " static transforms, static-edit reps limited to " + std::to_string(staticReps));
    }
    progress("sync: " + size + ", static edit");
    const std::size_t stride = available / (static_cast<std::size_t>(staticReps) + 1);
    EditSamples samples;
    const TimingSummary t = measureRepeated(staticReps, [&](int k) {
      Transform& xf = *g.staticLeaves[static_cast<std::size_t>(k) * stride + stride / 2];
      const Vec3f moved = xf.translation.getValue() + Vec3f(0.0f, 0.05f, 0.0f);
      const double editMs = timeMs([&] { xf.translation = moved; });
      FrameStats stats;
      const double ms = timeMs([&] { stats = graph.sync(); });
      if (k > 0) samples.add(editMs, stats, graph.debugStats());
      return ms;
    });
    BenchRow& row = addRow(report, size + ", static edit", "tracegraph-sync", t);
    addCommon(row);
    samples.addTo(row);
  }
}

/// Frame `step` of a run that starts at the scene's first frame and wraps at its end.
int frameOfStep(const SceneTiming& timing, int step) {
  return step % std::max(1, timing.frames);
}

void runFrameCase(BenchReport& report, const CommonOptions& common, const SceneSource& source,
                  int reps) {
  const SceneTiming& timing = source.timing;
  // Frame 0 is the initial build (untimed), frame 1 the warm-up, frames 2..reps+1 the samples;
  // each step is from one frame to the next, as when playing the animation.
  const int firstFrame = frameOfStep(timing, 2);
  const int lastFrame = frameOfStep(timing, reps + 1);
  const std::string caseName = source.name + " frame step";

  SceneGraph graph;
  graph.setRoot(source.root);
  graph.advanceTo(timing.timeOf(0));
  FrameStats first;
  const double firstMs = timeMs([&] { first = graph.sync(); });
  if (first.instances == 0) throw Error(source.name + ": the scene has no geometry to sync");

  progress("sync: " + source.name + ", tracegraph-frame-sync");
  std::vector<double> rebuildMs, topLevelMs, syncMinusTopLevelMs, objectsRebuilt, trianglesRebuilt;
  FrameStats last;
  const TimingSummary ours = measureRepeated(reps, [&](int k) {
    FrameStats stats;
    const double ms = timeMs([&] {
      graph.advanceTo(timing.timeOf(frameOfStep(timing, k + 1)));
      stats = graph.sync();
    });
    if (k > 0) {
      rebuildMs.push_back(stats.rebuildMs);
      topLevelMs.push_back(stats.toplevelMs);
      syncMinusTopLevelMs.push_back(stats.syncMs - stats.toplevelMs);
      objectsRebuilt.push_back(static_cast<double>(stats.objectsRebuilt));
      trianglesRebuilt.push_back(static_cast<double>(stats.trianglesRebuilt));
      last = stats;
    }
    return ms;
  });
  {
    BenchRow& row = addRow(report, caseName, "tracegraph-frame-sync", ours);
    row.extra.push_back(realField("rebuild_ms", median(rebuildMs)));
    row.extra.push_back(realField("toplevel_ms", median(topLevelMs)));
    row.extra.push_back(realField("sync_minus_toplevel_ms", median(syncMinusTopLevelMs)));
    row.extra.push_back(realField("objects_rebuilt", median(objectsRebuilt)));
    row.extra.push_back(realField("triangles_rebuilt", median(trianglesRebuilt)));
    row.extra.push_back(intField("instances", static_cast<std::int64_t>(last.instances)));
    row.extra.push_back(
        intField("static_triangles", static_cast<std::int64_t>(last.triangles.statics)));
    row.extra.push_back(
        intField("rigid_triangles", static_cast<std::int64_t>(last.triangles.rigid)));
    row.extra.push_back(
        intField("deforming_triangles", static_cast<std::int64_t>(last.triangles.deforming)));
    row.extra.push_back(intField("first_frame", firstFrame));
    row.extra.push_back(intField("last_frame", lastFrame));
    row.extra.push_back(intField("scene_frames", timing.frames));
    row.extra.push_back(realField("first_sync_ms", firstMs));
  }

#ifdef TG_HAVE_EMBREE
  // The same frames again, each synced untimed and then flattened from the backend scene into
  // one Embree geometry: the flat approach sees exactly the triangles Tracegraph holds.
  progress("sync: " + source.name + ", embree-low-flat");
  EmbreeFlatScene flat(common.threads, common.embreeConfig);
  std::vector<double> copyMs, copyAndBuildMs;
  const TimingSummary build = measureRepeated(reps, [&](int k) {
    graph.advanceTo(timing.timeOf(frameOfStep(timing, k + 1)));
    graph.sync();
    const std::vector<InstanceId> instances = graph.instanceIds();
    const double copy = timeMs([&] { flat.flatten(graph.backendScene(), instances); });
    const double ms = timeMs([&] { flat.commit(); });
    if (k > 0) {
      copyMs.push_back(copy);
      copyAndBuildMs.push_back(copy + ms);
    }
    return ms;
  });
  // Ratio of the flat approach's frame to ours: above 1, the flat rebuild is that many times
  // slower.
  auto ratio = [&](const TimingSummary& t) {
    return ours.medianMs > 0.0 ? t.medianMs / ours.medianMs : 0.0;
  };
  {
    BenchRow& row = addRow(report, caseName, "embree-low-flat", build);
    row.extra.push_back(intField("triangles", static_cast<std::int64_t>(flat.triangleCount())));
    row.extra.push_back(realField("flat_over_tracegraph", ratio(build)));
  }
  {
    const TimingSummary both = summarize(copyAndBuildMs);
    BenchRow& row = addRow(report, caseName, "embree-low-flat+copy", both);
    row.extra.push_back(realField("copy_ms", median(copyMs)));
    row.extra.push_back(realField("flat_over_tracegraph", ratio(both)));
    row.extra.push_back(
        intField("topology_changes", static_cast<std::int64_t>(flat.topologyChanges())));
  }
#else
  (void)common;
#endif
}

}  // namespace

BenchReport runSyncSuite(const CommonOptions& common, const SyncSuiteOptions& options) {
  const int reps = repsOrDefault(common, kDefaultSyncReps);
  // Loaded first, so that a scene that cannot be loaded fails before minutes of edit cases.
  const SceneSource source = loadSceneSource(options.scene, kFps);
  for (const std::string& w : source.warnings) progress("warning: " + w);
  BenchReport report = startReport("sync", common);
  for (const std::size_t n : options.nodes) runEditCases(report, n, reps);
  runFrameCase(report, common, source, reps);
  return report;
}

}  // namespace tg::bench
