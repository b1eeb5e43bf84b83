/// @file BenchScene.h
/// A scene as the benchmarks consume it: a flat list of meshes and of instances of them. Every
/// source (built-in generators today, the scene-file loaders later) produces this form, and
/// every implementation under test (Tracegraph, Embree) is built from it, so they all see the
/// same geometry.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/render/Camera.h"

namespace tg::bench {

/// One placement of a mesh; scene graphs are flattened into these with composed matrices.
struct BenchInstance {
  std::uint32_t mesh = 0;  ///< index into BenchScene::meshes
  Affine3d objectToWorld;
};

/// Meshes and instances of one benchmark scene.
struct BenchScene {
  std::string name;  ///< what the user asked for, e.g. "builtin:sphereflake"
  std::vector<TriangleMesh> meshes;
  std::vector<BenchInstance> instances;
  /// The scene file's own camera at the frame loaded (image size left to the suite); empty for
  /// built-in scenes and files without a camera.
  std::optional<CameraParams> camera;

  /// Triangles summed over instances.
  std::size_t instancedTriangleCount() const;
};

/// Adds the scene to `scene`: one Static object per mesh and one instance per BenchInstance,
/// in order, so that Tracegraph's object and instance ids equal the indices into `bench.meshes`
/// and `bench.instances` (hit records of different implementations compare directly). Does not
/// commit. `scene` must be empty.
void populateScene(const BenchScene& bench, Scene& scene);

}  // namespace tg::bench
