/// @file Texture.h
/// Image texture applied to the shapes that follow.
#pragma once

#include <string>

#include "tracegraph/scenegraph/SField.h"
#include "tracegraph/scenegraph/TextureNode.h"

namespace tg::nodes {

/// Sets the current texture (an image file) for the shapes that follow; texture
/// coordinates come from the mesh (Inventor SoTexture2, VRML ImageTexture).
class Texture : public TextureNode {
 public:
  /// A new texture without file.
  static ref_ptr<Texture> create() { return ref_ptr<Texture>(new Texture()); }
  /// A new texture reading `file`.
  static ref_ptr<Texture> create(std::string file) {
    ref_ptr<Texture> t = create();
    t->filename.setValue(std::move(file));
    return t;
  }
  std::string_view className() const override { return "Texture"; }
  const std::string& fileName() const override { return filename.getValue(); }

  /// Image file, as written in the scene.
  SFString filename{*this, "filename", ChangeKind::Material};

 protected:
  Texture() = default;
};

}  // namespace tg::nodes
