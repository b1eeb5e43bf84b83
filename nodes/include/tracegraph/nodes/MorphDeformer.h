/// @file MorphDeformer.h
/// Weighted blend of morph targets (blend shapes).
#pragma once

#include "tracegraph/nodes/Deformer.h"

namespace tg::nodes {

/// Outputs base + sum_j weights[j] * (target_j - base). `targets` holds weights.size() lists
/// of n absolute positions one after the other (glTF stores offsets: add the base first).
/// Drive `weights` from interpolators or set it directly.
class MorphDeformer : public Deformer {
 public:
  /// A new deformer without targets.
  static ref_ptr<MorphDeformer> create() { return ref_ptr<MorphDeformer>(new MorphDeformer()); }
  std::string_view className() const override { return "MorphDeformer"; }
  void evaluate(double time) override;

  /// Points of the undeformed mesh.
  MFVec3f basePoints{*this, "basePoints", ChangeKind::Parameter};
  /// weights.size() lists of n absolute positions.
  MFVec3f targets{*this, "targets", ChangeKind::Parameter};
  /// Input: one weight per target.
  MFFloat weights{*this, "weights", ChangeKind::Parameter};

 protected:
  MorphDeformer() = default;
  bool producesNormals() const override { return false; }
};

}  // namespace tg::nodes
