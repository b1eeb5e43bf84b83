/// @file MaterialNode.h
/// The material role and the plain material parameters renderers read per hit.
#pragma once

#include "tracegraph/scenegraph/Color.h"
#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Material parameters as BART/NFF and Inventor describe them (Phong plus transmission).
struct MaterialData {
  Color ambient{0.2f, 0.2f, 0.2f};   ///< reflectance for the ambient light
  Color diffuse{0.8f, 0.8f, 0.8f};   ///< Lambert reflectance
  Color specular{0.0f, 0.0f, 0.0f};  ///< highlight colour and mirror reflectance
  Color emissive{0.0f, 0.0f, 0.0f};  ///< light emitted by the surface
  float shininess = 0.2f;            ///< Phong exponent as given by the file (renderer scales it)
  float transmittance = 0.0f;        ///< 0 opaque ... 1 fully transmissive
  float ior = 1.0f;                  ///< index of refraction for transmitted rays
};

/// Role of Material: sets the current material for the shapes that follow.
class MaterialNode : public Node {
 public:
  /// The parameters as they are now.
  virtual MaterialData materialData() const = 0;
  void accept(NodeVisitor& visitor) override;

 protected:
  MaterialNode() = default;
};

}  // namespace tg
