/// @file TransformNode.h
/// The transform role: a node that multiplies the current matrix by a local one.
#pragma once

#include "tracegraph/backend/Affine.h"
#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// Role of Transform and MatrixTransform: during traversal the current matrix becomes
/// current * localMatrix() for the nodes that follow, until the enclosing Separator ends.
class TransformNode : public Node {
 public:
  /// The local matrix, composed in double.
  virtual Affine3d localMatrix() const = 0;
  void accept(NodeVisitor& visitor) override;

 protected:
  TransformNode() = default;
};

}  // namespace tg
