/// @file Deformer.h
/// Base of the animators that compute a mesh's points every frame.
#pragma once

#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/scenegraph/Animator.h"
#include "tracegraph/scenegraph/MField.h"

namespace tg::nodes {

/// An animator whose outputs are a mesh's points (and optionally normals). A mesh connected
/// from a deformer is deforming from its first frame: its own object, rebuilt with the fast
/// builder in every frame its points change.
class Deformer : public Animator {
 public:
  /// Connects `mesh`'s points (and normals, when this deformer produces them) from this
  /// deformer's outputs.
  void drive(Mesh& mesh);

  /// Output: deformed points.
  MFVec3f points_changed{*this, "points_changed", ChangeKind::Parameter};
  /// Output: deformed normals (empty when the deformer has no rest normals).
  MFVec3f normals_changed{*this, "normals_changed", ChangeKind::Parameter};

 protected:
  Deformer() = default;
  /// True when evaluate() fills normals_changed.
  virtual bool producesNormals() const = 0;
};

}  // namespace tg::nodes
