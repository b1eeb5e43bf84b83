/// @file TextureNode.h
/// The texture role: an image file applied to the shapes that follow.
#pragma once

#include <string>

#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Role of Texture: sets the current texture image for the shapes that follow.
class TextureNode : public Node {
 public:
  /// The image file name, as written in the scene (resolved by the renderer).
  virtual const std::string& fileName() const = 0;
  void accept(NodeVisitor& visitor) override;

 protected:
  TextureNode() = default;
};

}  // namespace tg
