/// @file PrimaryScene.h
/// What the scene suites against Embree (`static`, `overhead`, `scaling`) share: a scene, its
/// flattened copy, the primary rays framing it and one judge for every trace of those rays.
#pragma once

#include <tbb/task_arena.h>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "BenchReport.h"
#include "FlattenedScene.h"
#include "ImageJudge.h"
#include "Suites.h"
#include "tracegraph/backend/Scene.h"

namespace tg::bench {

/// A scene loaded for primary-ray rows; everything is judged in the ids of the instanced scene.
class PrimaryScene {
 public:
  /// Loads options.scene (throws tg::Error as loadBenchScene), flattens it, frames its bounds
  /// with options.size primary rays and renders the reference's answers (in `arena`).
  PrimaryScene(const PeerSceneOptions& options, tbb::task_arena& arena);

  /// The scene as loaded (instances as the scene graph produces them).
  const BenchScene& bench() const { return bench_; }
  /// The same triangles in one world-space mesh.
  const Flattened& flat() const { return flat_; }
  /// Row-major primary rays of the image.
  std::span<const Ray> rays() const { return rays_; }
  /// "<scene> primary WxH".
  const std::string& caseName() const { return caseName_; }

  /// Adds the reference's judgement (ref_mismatches, judged, psnr_db, flip_mean) of `outcomes`
  /// to `row`; `flattened` outcomes carry ids of flat() and are mapped back first.
  void judge(BenchRow& row, std::vector<RayOutcome> outcomes, bool flattened) const;

 private:
  BenchScene bench_;
  Flattened flat_;
  Scene judgeScene_;
  std::vector<Ray> rays_;
  std::string caseName_;
  std::unique_ptr<PrimaryImageJudge> judge_;
};

}  // namespace tg::bench
