#include "FlattenedScene.h"

namespace tg::bench {

Flattened flatten(const BenchScene& bench) {
  Flattened f;
  f.scene.name = bench.name + " flattened";
  TriangleMesh mesh;
  for (std::size_t i = 0; i < bench.instances.size(); ++i) {
    const BenchInstance& inst = bench.instances[i];
    const TriangleMesh& m = bench.meshes[inst.mesh];
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    // Transformed in double and rounded to float once.
    for (const Vec3f& p : m.positions)
      mesh.positions.push_back(Vec3f(inst.objectToWorld.transformPoint(Vec3d(p))));
    for (const std::uint32_t index : m.indices) mesh.indices.push_back(base + index);
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
      f.origin.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(t)});
  }
  f.scene.meshes.push_back(std::move(mesh));
  f.scene.instances.push_back({0, Affine3d{}});
  return f;
}

void unflatten(const Flattened& flat, std::vector<RayOutcome>& outcomes) {
  for (RayOutcome& o : outcomes)
    if (o.hit()) o = flat.origin[o.prim];
}

}  // namespace tg::bench
