// The memory suite: bytes per triangle of every accelerator we build and of Embree's builds,
// each with the mesh it keeps. Ours come from BuildStats::bytes and the mesh's arrays; Embree's
// from its memory monitor, which sees every byte the device allocates (geometry buffers,
// acceleration structure, allocator blocks) and so includes what a caller cannot see.
#include <tbb/task_arena.h>

#include <memory>

#include "BenchSceneLoader.h"
#include "BenchTiming.h"
#include "FlattenedScene.h"
#include "SuiteCommon.h"
#include "Suites.h"
#include "tracegraph/backend/ObjectAccel.h"

#ifdef TG_HAVE_EMBREE
#include "EmbreePeer.h"
#endif

namespace tg::bench {
namespace {

std::size_t meshBytes(const TriangleMesh& mesh) {
  return mesh.positions.size() * sizeof(Vec3f) + mesh.indices.size() * sizeof(std::uint32_t) +
         mesh.normals.size() * sizeof(Vec3f) + mesh.uvs.size() * sizeof(Vec2f);
}

void addBytes(BenchRow& row, std::int64_t accel, std::int64_t mesh, std::size_t triangles) {
  const double n = static_cast<double>(std::max<std::size_t>(triangles, 1));
  row.extra.push_back(intField("accel_bytes", accel));
  row.extra.push_back(intField("mesh_bytes", mesh));
  row.extra.push_back(realField("accel_bytes_per_triangle", static_cast<double>(accel) / n));
  row.extra.push_back(realField("bytes_per_triangle", static_cast<double>(accel + mesh) / n));
}

}  // namespace

BenchReport runMemorySuite(const CommonOptions& common, const PeerSceneOptions& options) {
  const int reps = repsOrDefault(common, kDefaultBuildReps);
  tbb::task_arena arena(common.threads);
  // One mesh, so that every row is one structure over the same triangles.
  const Flattened flat = flatten(loadBenchScene(options.scene));
  const TriangleMesh& mesh = flat.scene.meshes.front();
  const std::size_t triangles = mesh.triangleCount();
  BenchReport report = startReport("memory", common);
  const std::string caseName =
      "memory: " + options.scene + " (" + std::to_string(triangles) + " triangles)";

  for (const AccelKind kind :
       {AccelKind::Bvh, AccelKind::BvhFast, AccelKind::SahKdTree, AccelKind::FastKdTree}) {
    const std::string impl = "tracegraph-" + std::string(accelKindName(kind));
    progress("memory: " + impl);
    const std::unique_ptr<ObjectAccel> accel = createObjectAccel(kind);
    const TimingSummary t = measureRepeated(
        reps, [&](int) { return timeMs([&] { arena.execute([&] { accel->build(mesh); }); }); });
    addBytes(addRow(report, caseName, impl, t), static_cast<std::int64_t>(accel->stats().bytes),
             static_cast<std::int64_t>(meshBytes(mesh)), triangles);
  }

#ifdef TG_HAVE_EMBREE
  for (const EmbreeQuality quality :
       {EmbreeQuality::Low, EmbreeQuality::Medium, EmbreeQuality::High, EmbreeQuality::Refit}) {
    progress("memory: " + embreeImplName(quality));
    // A device of its own per quality, so that nothing another build left cached is counted.
    EmbreeDevice device(common.threads, common.embreeConfig, true);
    const std::int64_t before = device.allocatedBytes();
    std::int64_t geometry = 0, built = 0;
    {
      EmbreeBenchScene peer(device, flat.scene, quality);
      geometry = device.allocatedBytes() - before;
      arena.execute([&] { peer.commit(); });
      device.check("committing the scene");
      built = device.allocatedBytes() - before - geometry;
    }
    const TimingSummary t = timeEmbreeBuilds(device, flat.scene, quality, reps);
    addBytes(addRow(report, caseName, embreeImplName(quality), t), built, geometry, triangles);
  }
  // Our bytes against Embree's default quality.
  const auto totalBytes = [](const BenchRow& row) {
    std::int64_t sum = 0;
    for (const ExtraField& f : row.extra)
      if (f.key == "accel_bytes" || f.key == "mesh_bytes") sum += std::get<std::int64_t>(f.value);
    return sum;
  };
  std::int64_t medium = 0;
  for (const BenchRow& row : report.rows)
    if (row.impl == embreeImplName(EmbreeQuality::Medium)) medium = totalBytes(row);
  for (BenchRow& row : report.rows)
    if (row.impl.rfind("tracegraph", 0) == 0 && medium > 0)
      row.extra.push_back(realField("bytes_vs_embree_medium", static_cast<double>(totalBytes(row)) /
                                                                  static_cast<double>(medium)));
#endif
  return report;
}

}  // namespace tg::bench
