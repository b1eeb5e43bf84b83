/// @file MatrixTransform.h
/// Transform node given as a full affine matrix.
#pragma once

#include "tracegraph/scenegraph/SField.h"
#include "tracegraph/scenegraph/TransformNode.h"

namespace tg::nodes {

/// Multiplies the current matrix by `matrix` (Inventor SoMatrixTransform; glTF node matrices,
/// BART transforms).
class MatrixTransform : public TransformNode {
 public:
  /// A new identity transform.
  static ref_ptr<MatrixTransform> create() {
    return ref_ptr<MatrixTransform>(new MatrixTransform());
  }
  /// A new transform with the given matrix.
  static ref_ptr<MatrixTransform> create(const Affine3d& m) {
    ref_ptr<MatrixTransform> t = create();
    t->matrix.setValue(m);
    return t;
  }
  std::string_view className() const override { return "MatrixTransform"; }
  Affine3d localMatrix() const override { return matrix.getValue(); }

  /// The local matrix.
  SFMatrix matrix{*this, "matrix", ChangeKind::Transform};

 protected:
  MatrixTransform() = default;
};

}  // namespace tg::nodes
