#include "tracegraph/backend/render/RenderScene.h"

namespace tg {
namespace {

const Material kDefaultMaterial{};

std::string checkIndex(std::uint32_t index, std::size_t count, const std::string& where) {
  if (index != kInvalidId && index >= count)
    return where + ": material " + std::to_string(index) + " out of range (" +
           std::to_string(count) + " materials)";
  return {};
}

}  // namespace

const Material& RenderScene::material(std::uint32_t instanceId, std::uint32_t objectId,
                                      std::uint32_t primId) const {
  const std::uint32_t index = materialIndex(instanceId, objectId, primId);
  return index < materials.size() ? materials[index] : kDefaultMaterial;
}

DynamicsClass RenderScene::dynamicsClass(std::uint32_t instanceId) const {
  if (instanceId < instanceClasses.size()) return instanceClasses[instanceId];
  if (scene == nullptr) return DynamicsClass::Static;
  switch (scene->objectUsage(scene->instanceObject(instanceId))) {
    case ObjectUsage::Static:
      return DynamicsClass::Static;
    case ObjectUsage::Rigid:
      return DynamicsClass::Rigid;
    case ObjectUsage::Deforming:
      return DynamicsClass::Deforming;
  }
  return DynamicsClass::Static;
}

std::string RenderScene::validate() const {
  if (scene == nullptr) return "RenderScene: no scene";
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const Material& m = materials[i];
    const std::string problem = m.validate();
    if (!problem.empty()) return "RenderScene: material " + std::to_string(i) + ": " + problem;
    if (m.texture != kInvalidId && (m.texture >= textures.size() || !textures[m.texture]))
      return "RenderScene: material " + std::to_string(i) + ": texture " +
             std::to_string(m.texture) + " missing";
  }
  for (std::size_t o = 0; o < objectMaterials.size(); ++o) {
    std::string p = checkIndex(objectMaterials[o], materials.size(),
                               "RenderScene: object " + std::to_string(o));
    if (!p.empty()) return p;
  }
  for (std::size_t o = 0; o < primitiveMaterials.size(); ++o)
    for (std::size_t k = 0; k < primitiveMaterials[o].size(); ++k) {
      std::string p = checkIndex(
          primitiveMaterials[o][k], materials.size(),
          "RenderScene: object " + std::to_string(o) + " primitive " + std::to_string(k));
      if (!p.empty()) return p;
    }
  for (std::size_t i = 0; i < instanceMaterials.size(); ++i) {
    std::string p = checkIndex(instanceMaterials[i], materials.size(),
                               "RenderScene: instance " + std::to_string(i));
    if (!p.empty()) return p;
  }
  for (std::size_t i = 0; i < instanceMaterialRanges.size(); ++i) {
    const auto& ranges = instanceMaterialRanges[i];
    for (std::size_t k = 0; k < ranges.size(); ++k) {
      if (k > 0 && ranges[k].primBegin < ranges[k - 1].primBegin)
        return "RenderScene: instance " + std::to_string(i) + ": material ranges not sorted";
      std::string p =
          checkIndex(ranges[k].material, materials.size(),
                     "RenderScene: instance " + std::to_string(i) + " range " + std::to_string(k));
      if (!p.empty()) return p;
    }
  }
  for (const PointLight& l : pointLights)
    if (!isFinite(l.position) || !isFinite(l.color)) return "RenderScene: point light is NaN";
  for (const DirectionalLight& l : directionalLights)
    if (!isFinite(l.direction) || !isFinite(l.color) || dot(l.direction, l.direction) == 0.0f)
      return "RenderScene: directional light is NaN or has no direction";
  for (const SpotLight& l : spotLights)
    if (!isFinite(l.position) || !isFinite(l.direction) || !isFinite(l.color) ||
        dot(l.direction, l.direction) == 0.0f)
      return "RenderScene: spot light is NaN or has no direction";
  if (!isFinite(ambient) || !isFinite(background))
    return "RenderScene: ambient or background is NaN";
  return {};
}

}  // namespace tg
