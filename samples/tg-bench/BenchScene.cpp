#include "BenchScene.h"

#include "tracegraph/backend/Error.h"

namespace tg::bench {

std::size_t BenchScene::instancedTriangleCount() const {
  std::size_t n = 0;
  for (const BenchInstance& inst : instances) n += meshes.at(inst.mesh).triangleCount();
  return n;
}

void populateScene(const BenchScene& bench, Scene& scene) {
  if (scene.objectCount() != 0 || scene.instanceCount() != 0)
    throw Error("populateScene: the target scene is not empty");
  for (std::size_t i = 0; i < bench.meshes.size(); ++i) {
    if (scene.createObject(bench.meshes[i], ObjectUsage::Static) != i)
      throw Error("populateScene: object ids are not sequential");
  }
  for (std::size_t i = 0; i < bench.instances.size(); ++i) {
    const BenchInstance& inst = bench.instances[i];
    if (scene.createInstance(inst.mesh, inst.objectToWorld) != i)
      throw Error("populateScene: instance ids are not sequential");
  }
}

}  // namespace tg::bench
