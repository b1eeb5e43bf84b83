/// @file Material.h
/// Phong material with transmission, as BART/NFF and Inventor describe surfaces.
#pragma once

#include "tracegraph/scenegraph/MaterialNode.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Sets the current material for the shapes that follow (inside the enclosing Separator).
/// Changing it needs no backend work: hits map to the node, which the renderer reads.
class Material : public MaterialNode {
 public:
  /// A new material with Inventor's defaults (grey diffuse).
  static ref_ptr<Material> create() { return ref_ptr<Material>(new Material()); }
  std::string_view className() const override { return "Material"; }
  MaterialData materialData() const override;

  /// Reflectance for the ambient light.
  SFColor ambientColor{*this, "ambientColor", ChangeKind::Material, Color{0.2f, 0.2f, 0.2f}};
  /// Lambert reflectance.
  SFColor diffuseColor{*this, "diffuseColor", ChangeKind::Material, Color{0.8f, 0.8f, 0.8f}};
  /// Phong highlight colour and mirror reflectance.
  SFColor specularColor{*this, "specularColor", ChangeKind::Material};
  /// Light emitted by the surface itself.
  SFColor emissiveColor{*this, "emissiveColor", ChangeKind::Material};
  /// Phong exponent as given by the file.
  SFFloat shininess{*this, "shininess", ChangeKind::Material, 0.2f};
  /// 0 opaque ... 1 fully transmissive.
  SFFloat transmittance{*this, "transmittance", ChangeKind::Material, 0.0f};
  /// Index of refraction of transmitted rays.
  SFFloat ior{*this, "ior", ChangeKind::Material, 1.0f};

 protected:
  Material() = default;
};

}  // namespace tg::nodes
