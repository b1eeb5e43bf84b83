// The load suite: what opening a BART/NFF scene costs, stage by stage: parsing the file (with
// its includes), building the node graph, and the first SceneGraph sync (classification plus
// every object and the top level built from scratch).
#include <cstdint>
#include <string>

#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/loaders/AffParser.h"
#include "tracegraph/scenegraph/SceneGraph.h"

namespace tg::bench {
namespace {

std::int64_t asInt(std::size_t n) {
  return static_cast<std::int64_t>(n);
}

}  // namespace

BenchReport runLoadSuite(const CommonOptions& common, const LoadOptions& options) {
  const int reps = repsOrDefault(common, kDefaultLoadReps);
  const std::string& path = options.scene;
  if (!isAffPath(path))
    throw Error("cannot load '" + path + "': the load suite reads .aff and .nff files");
  BenchReport report = startReport("load", common);

  progress("load: tracegraph-aff-parse");
  {
    AffDocument doc;
    // The previous sample's document is freed before the timer starts (assignment would
    // otherwise free it inside the measurement).
    const TimingSummary t = measureRepeated(reps, [&](int) {
      doc = AffDocument{};
      return timeMs([&] { doc = parseAffFile(path); });
    });
    const AffTriangleCounts n = doc.countTriangles();
    BenchRow& row = addRow(report, path, "tracegraph-aff-parse", t);
    row.extra.push_back(intField("files", asInt(doc.files.size())));
    row.extra.push_back(intField("includes", asInt(doc.includeCount)));
    row.extra.push_back(intField("primitives", asInt(n.meshCount)));
    row.extra.push_back(intField("triangles", asInt(n.total())));
    row.extra.push_back(intField("materials", asInt(doc.materials.size())));
    row.extra.push_back(intField("tracks", asInt(doc.tracks.size())));
  }

  progress("load: tracegraph-aff-load");
  AffScene scene;
  {
    const TimingSummary t = measureRepeated(reps, [&](int) {
      scene = AffScene{};
      return timeMs([&] { scene = loadAff(path); });
    });
    BenchRow& row = addRow(report, path, "tracegraph-aff-load", t);
    row.extra.push_back(intField("triangles", asInt(scene.triangles.total())));
    row.extra.push_back(intField("animators", asInt(scene.animators.size())));
    row.extra.push_back(intField("lights", asInt(scene.lights.size())));
    row.extra.push_back(intField("warnings", asInt(scene.warnings.size())));
  }

  progress("load: tracegraph-aff-sync");
  {
    FrameStats stats;
    std::size_t objects = 0;
    const TimingSummary t = measureRepeated(reps, [&](int) {
      // A fresh graph per sample: setRoot and advanceTo are setup, the first sync (traversal,
      // classification, static chunks, every object build and the top level) is measured.
      SceneGraph graph;
      graph.setRoot(scene.root);
      graph.advanceTo(scene.frameTime(0));
      const double ms = timeMs([&] { stats = graph.sync(); });
      objects = graph.backendScene().objectCount();
      return ms;
    });
    BenchRow& row = addRow(report, path, "tracegraph-aff-sync", t);
    row.extra.push_back(intField("objects", asInt(objects)));
    row.extra.push_back(intField("instances", asInt(stats.instances)));
    row.extra.push_back(intField("static_triangles", asInt(stats.triangles.statics)));
    row.extra.push_back(intField("rigid_triangles", asInt(stats.triangles.rigid)));
    row.extra.push_back(intField("deforming_triangles", asInt(stats.triangles.deforming)));
  }
  return report;
}

}  // namespace tg::bench
