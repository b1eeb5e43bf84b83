#include "PrimaryScene.h"

#include "BenchSceneLoader.h"
#include "ReferenceJudge.h"
#include "SuiteCommon.h"
#include "tracegraph/backend/Error.h"

namespace tg::bench {

PrimaryScene::PrimaryScene(const PeerSceneOptions& options, tbb::task_arena& arena)
    : bench_(loadBenchScene(options.scene)), flat_(flatten(bench_)) {
  populateScene(bench_, judgeScene_);
  arena.execute([&] { judgeScene_.commit(); });
  const Box3f bounds = judgeScene_.bounds();
  if (bounds.empty()) throw Error("scene '" + options.scene + "' has no triangles to trace");
  const bool sceneView = options.view == "scene";
  if (sceneView && !bench_.camera)
    throw Error("--view scene: '" + options.scene + "' has no camera of its own");
  rays_ = sceneView ? makePrimaryRays(*bench_.camera, options.size)
                    : makePrimaryRays(frameBounds(bounds, options.size), options.size);
  caseName_ = options.scene + " primary " + std::to_string(options.size.width) + "x" +
              std::to_string(options.size.height) + (sceneView ? " scene view" : "");
  progress("rendering the reference of " + caseName_);
  arena.execute([&] {
    judge_ = std::make_unique<PrimaryImageJudge>(judgeScene_, rays_, options.size, options.judged);
  });
}

void PrimaryScene::judge(BenchRow& row, std::vector<RayOutcome> outcomes, bool flattened) const {
  if (flattened) unflatten(flat_, outcomes);
  judge_->judge(row, outcomes);
}

}  // namespace tg::bench
