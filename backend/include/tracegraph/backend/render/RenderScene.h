/// @file RenderScene.h
/// Everything the renderer needs besides the geometry in tg::Scene: lights, ambient and
/// background colours, materials and textures, and which material each triangle uses.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tracegraph/backend/DynamicsClass.h"
#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/render/Light.h"
#include "tracegraph/backend/render/Material.h"
#include "tracegraph/backend/render/Texture.h"

namespace tg {

/// The shading side of a frame. Plain data: fill the vectors, then render. The renderer only
/// reads it, so one RenderScene may serve several concurrent renders.
///
/// Material lookup for a hit (instance i, object o, primitive p), first match wins:
///  1. instanceMaterials[i] when present and not kInvalidId (per-instance override, e.g. a
///     highlighted selection or a scene-graph Material node above a shared object);
///  1b. instanceMaterialRanges[i] when non-empty: the range with the largest primBegin <= p
///     (a scene graph merges meshes with different materials into one object, and two
///     instances of a shared object may sit under different materials);
///  2. primitiveMaterials[o][p] when that table is non-empty and the entry is not kInvalidId
///     (NFF/AFF files switch material between the polygons of one object);
///  3. objectMaterials[o] when present and not kInvalidId;
///  4. the built-in default material (Material{}: grey diffuse).
struct RenderScene {
  const Scene* scene = nullptr;  ///< the committed geometry; must outlive the render

  std::vector<PointLight> pointLights;              ///< NFF/AFF `l`, X3D PointLight
  std::vector<DirectionalLight> directionalLights;  ///< X3D DirectionalLight
  std::vector<SpotLight> spotLights;                ///< X3D SpotLight
  Vec3f ambient{0.0f, 0.0f, 0.0f};     ///< ambient light, multiplied by Material::ambient
  Vec3f background{0.0f, 0.0f, 0.0f};  ///< colour of rays that hit nothing

  std::vector<Material> materials;  ///< indexed by the tables below
  /// Textures referenced by Material::texture. Shared so that scenes can reuse loaded images.
  std::vector<std::shared_ptr<const Texture>> textures;

  std::vector<std::uint32_t> objectMaterials;  ///< by ObjectId: default material of the object
  /// By ObjectId: empty, or one material index per triangle of the object.
  std::vector<std::vector<std::uint32_t>> primitiveMaterials;
  std::vector<std::uint32_t> instanceMaterials;  ///< by InstanceId: override, or kInvalidId

  /// A material for the triangles from primBegin up to the next range's primBegin.
  struct MaterialRange {
    /// First triangle of the range.
    std::uint32_t primBegin = 0;
    /// Index into materials.
    std::uint32_t material = kInvalidId;
  };
  /// By InstanceId: empty, or ranges sorted by primBegin (the first starting at 0).
  std::vector<std::vector<MaterialRange>> instanceMaterialRanges;

  /// By InstanceId: dynamics class for the `classes` mode. Instances without an entry take it
  /// from their object's usage (Static, Rigid, Deforming map one to one).
  std::vector<DynamicsClass> instanceClasses;

  /// The material index for a hit, or kInvalidId for the built-in default (see above).
  std::uint32_t materialIndex(std::uint32_t instanceId, std::uint32_t objectId,
                              std::uint32_t primId) const {
    return materialIndexWith(instanceId, objectId, primId, &RenderScene::rangeContaining);
  }

  /// materialIndex with the range of rule 1b found by `findRange(ranges, primId)`, which must
  /// return what rangeContaining returns (a renderer may keep an index that finds it faster).
  template <typename FindRange>
  std::uint32_t materialIndexWith(std::uint32_t instanceId, std::uint32_t objectId,
                                  std::uint32_t primId, FindRange&& findRange) const {
    if (instanceId < instanceMaterials.size() && instanceMaterials[instanceId] != kInvalidId)
      return instanceMaterials[instanceId];
    if (instanceId < instanceMaterialRanges.size() && !instanceMaterialRanges[instanceId].empty()) {
      const std::vector<MaterialRange>& ranges = instanceMaterialRanges[instanceId];
      const std::uint32_t m = ranges[findRange(ranges, primId)].material;
      if (m != kInvalidId) return m;
    }
    if (objectId < primitiveMaterials.size()) {
      const std::vector<std::uint32_t>& perPrim = primitiveMaterials[objectId];
      if (primId < perPrim.size() && perPrim[primId] != kInvalidId) return perPrim[primId];
    }
    if (objectId < objectMaterials.size()) return objectMaterials[objectId];
    return kInvalidId;
  }

  /// The range of non-empty, sorted `ranges` that holds `primId`: the last one starting at or
  /// before it, or the first one when none does.
  static std::size_t rangeContaining(const std::vector<MaterialRange>& ranges,
                                     std::uint32_t primId) {
    std::size_t lo = 0, hi = ranges.size();
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      if (ranges[mid].primBegin <= primId)
        lo = mid;
      else
        hi = mid;
    }
    return lo;
  }

  /// The material for a hit (the built-in default when none is assigned).
  const Material& material(std::uint32_t instanceId, std::uint32_t objectId,
                           std::uint32_t primId) const;

  /// The dynamics class of an instance (see instanceClasses).
  DynamicsClass dynamicsClass(std::uint32_t instanceId) const;

  /// Empty when renderable, otherwise the first problem: no scene, an invalid material, a
  /// material index or texture index out of range, a null texture, a NaN light.
  std::string validate() const;
};

}  // namespace tg
